#include "jointhb/fe/mesh_file_error.hpp"

#include <gtest/gtest.h>

#include <string>

namespace jointhb::fe {
namespace {

TEST(MeshFileError, MessageIsFileLineProblem) {
  const MeshFileError error("model.inp", 12, "element 5: unknown node 17");
  EXPECT_EQ(std::string(error.what()), "model.inp:12: element 5: unknown node 17");
  EXPECT_EQ(error.file(), "model.inp");
  EXPECT_EQ(error.line(), 12);
  EXPECT_EQ(error.problem(), "element 5: unknown node 17");
}

TEST(MeshFileError, NoLineLeavesThePositionOutAndTheMessageStaysOnOneLine) {
  EXPECT_EQ(std::string(MeshFileError("a.msh", 0, "cannot be opened").what()),
            "a.msh: cannot be opened");
  EXPECT_EQ(std::string(MeshFileError("a\nb.msh", 3, "bad\r\nvalue").what()),
            "a b.msh:3: bad  value");
}

}  // namespace
}  // namespace jointhb::fe
