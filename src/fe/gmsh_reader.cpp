#include "jointhb/fe/gmsh_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <map>
#include <optional>
#include <stdexcept>
#include <unordered_map>
#include <utility>
#include <vector>

#include "jointhb/fe/mesh_file_error.hpp"
#include "text_fields.hpp"

namespace jointhb::fe {

std::string GmshOptions::validate() const {
  if (node_count(hex8_type) != 8) {
    return fmt::format("hex8_type: must be an 8-node type (C3D8 or C3D8I), got {}",
                       abaqus_name(hex8_type));
  }
  if (node_count(hex20_type) != 20) {
    return fmt::format("hex20_type: must be a 20-node type (C3D20 or C3D20R), got {}",
                       abaqus_name(hex20_type));
  }
  return {};
}

namespace {

// Gmsh element types (manual, "MSH file format": elementType).
constexpr int kTri3 = 2;
constexpr int kQuad4 = 3;
constexpr int kTet4 = 4;
constexpr int kHex8 = 5;
constexpr int kPrism6 = 6;
constexpr int kTri6 = 9;
constexpr int kTet10 = 11;
constexpr int kQuad8 = 16;
constexpr int kHex20 = 17;
constexpr int kPrism15 = 18;

std::string type_name(int type) {
  static const std::map<int, const char*> names = {
      {1, "2-node line"},        {2, "3-node triangle"},      {3, "4-node quadrangle"},
      {4, "4-node tetrahedron"}, {5, "8-node hexahedron"},    {6, "6-node prism"},
      {7, "5-node pyramid"},     {8, "3-node line"},          {9, "6-node triangle"},
      {10, "9-node quadrangle"}, {11, "10-node tetrahedron"}, {12, "27-node hexahedron"},
      {13, "18-node prism"},     {14, "14-node pyramid"},     {15, "point"},
      {16, "8-node quadrangle"}, {17, "20-node hexahedron"},  {18, "15-node prism"},
      {19, "13-node pyramid"}};
  const auto it = names.find(type);
  return it == names.end() ? fmt::format("type {}", type)
                           : fmt::format("type {} ({})", type, it->second);
}

// Abaqus local node i is Gmsh local node kGmshOfAbaqus[i]. Gmsh numbers the 20-node hexahedron's
// mid-edge nodes 8..19 by edge 0-1, 0-3, 0-4, 1-2, 1-5, 2-3, 2-6, 3-7, 4-5, 4-7, 5-6, 6-7;
// Abaqus by 0-1, 1-2, 2-3, 3-0, 4-5, 5-6, 6-7, 7-4, 0-4, 1-5, 2-6, 3-7.
constexpr std::array<int, 20> kGmshOfAbaqus = {
    0,  1,  2,  3,  4, 5, 6, 7,  // corners
    8,  11, 13, 9,               // edges 0-1, 1-2, 2-3, 3-0
    16, 18, 19, 17,              // edges 4-5, 5-6, 6-7, 7-4
    10, 12, 14, 15,              // edges 0-4, 1-5, 2-6, 3-7
};

// Gmsh's 10-node tetrahedron lists its mid-edge nodes by edge 0-1, 1-2, 2-0, 3-0, 3-2, 3-1 (the
// figure "Tetrahedron10" of the manual: node 8 on edge 2-3, node 9 on edge 1-3); Abaqus/VTK by
// 0-1, 1-2, 2-0, 0-3, 1-3, 2-3: Gmsh's nodes 8 and 9 are swapped.
constexpr std::array<int, 10> kGmshOfAbaqusTet10 = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8};

// Gmsh's 15-node prism (type 18; type 13 is the 18-node one) lists its mid-edge nodes by edge
// 0-1, 0-2, 0-3, 1-2, 1-4, 2-5, 3-4, 3-5, 4-5; Abaqus by 0-1, 1-2, 2-0, 3-4, 4-5, 5-3, 0-3, 1-4,
// 2-5. The corners agree (0-2 at w = -1 counter-clockwise seen from +w, 3-5 above them).
constexpr std::array<int, 15> kGmshOfAbaqusPrism15 = {0, 1, 2, 3,  4,  5,  6, 9,
                                                      7, 12, 14, 13, 8, 10, 11};

// The element type of a Gmsh volume element type other than the hexahedra, or none.
struct VolumeType {
  ElementType type;
  const int* gmsh_of_abaqus;  // nullptr: same order
};
std::optional<VolumeType> other_volume_type(int gmsh_type) {
  switch (gmsh_type) {
    case kTet4: return VolumeType{ElementType::tet4, nullptr};
    case kTet10: return VolumeType{ElementType::tet10, kGmshOfAbaqusTet10.data()};
    case kPrism6: return VolumeType{ElementType::wedge6, nullptr};
    case kPrism15: return VolumeType{ElementType::wedge15, kGmshOfAbaqusPrism15.data()};
    default: return std::nullopt;
  }
}

struct Line {
  int number = 0;
  std::vector<std::string_view> tokens;
};

struct RawElement {
  int line = 0;
  long tag = 0;
  std::vector<long> nodes;
};

struct ElementBlock {
  int line = 0;  // of the block header
  int dim = 0;
  int entity = 0;
  int type = 0;
  std::vector<RawElement> elements;
};

class GmshReader {
 public:
  GmshReader(std::string file, std::string_view text, const GmshOptions& options)
      : file_(std::move(file)), lines_(detail::split_lines(text)), options_(options) {}

  Mesh read() {
    bool have_format = false;
    while (next_ < lines_.size()) {
      const int number = static_cast<int>(next_) + 1;
      const std::string_view line = detail::trim(lines_[next_++]);
      if (line.empty()) continue;
      if (line.front() != '$' || line.starts_with("$End")) {
        fail(number, fmt::format("expected a section such as $Nodes, got '{}'", line));
      }
      const std::string section(line.substr(1));
      if (!have_format && section != "MeshFormat") {
        fail(number, "not a Gmsh MSH file: the first section must be $MeshFormat");
      }
      if (section == "MeshFormat") {
        read_format();
        have_format = true;
      } else if (section == "PhysicalNames") {
        read_physical_names();
      } else if (section == "Entities") {
        read_entities();
      } else if (section == "PartitionedEntities") {
        fail(number, "partitioned meshes are not supported (save without partitions)");
      } else if (section == "Nodes") {
        read_nodes();
      } else if (section == "Elements") {
        read_elements();
      } else {
        skip_section(section, number);
        continue;
      }
      expect_end(section);
    }
    if (!have_format) fail(0, "not a Gmsh MSH file: no $MeshFormat section");
    return build();
  }

 private:
  [[noreturn]] void fail(int line, const std::string& problem) const {
    throw MeshFileError(file_, line, problem);
  }

  // The next non-blank line, split at blanks; fails at the end of the file.
  Line next_line(const char* expected) {
    while (next_ < lines_.size()) {
      Line line{static_cast<int>(next_) + 1, detail::split_blanks(lines_[next_++])};
      if (!line.tokens.empty()) return line;
    }
    fail(static_cast<int>(lines_.size()), fmt::format("file ends where {} was expected", expected));
  }

  // The next line, which must have `count` tokens (or at least `count` when `at_least`).
  Line next_line(const char* expected, std::size_t count, bool at_least = false) {
    Line line = next_line(expected);
    if (line.tokens.front().starts_with("$")) {
      fail(line.number, fmt::format("expected {}, got '{}'", expected, line.tokens.front()));
    }
    if (line.tokens.size() < count || (!at_least && line.tokens.size() > count)) {
      fail(line.number, fmt::format("expected {}, got {} value(s)", expected, line.tokens.size()));
    }
    return line;
  }

  long integer(const Line& line, std::size_t i, const char* what) const {
    const auto value = i < line.tokens.size() ? detail::to_integer(line.tokens[i]) : std::nullopt;
    if (!value) {
      fail(line.number, fmt::format("{}: expected an integer, got '{}'", what,
                                    i < line.tokens.size() ? line.tokens[i] : ""));
    }
    return *value;
  }

  int small_integer(const Line& line, std::size_t i, const char* what) const {
    const long value = integer(line, i, what);
    if (value < -1'000'000'000L || value > 1'000'000'000L) {
      fail(line.number, fmt::format("{}: {} is out of range", what, value));
    }
    return static_cast<int>(value);
  }

  std::size_t count(const Line& line, std::size_t i, const char* what) const {
    const long value = integer(line, i, what);
    if (value < 0) fail(line.number, fmt::format("{}: must be >= 0, got {}", what, value));
    return static_cast<std::size_t>(value);
  }

  double number(const Line& line, std::size_t i, const char* what) const {
    const auto value = detail::to_number(line.tokens[i]);
    if (!value) {
      fail(line.number, fmt::format("{}: '{}' is not a finite number", what, line.tokens[i]));
    }
    return *value;
  }

  void expect_end(const std::string& section) {
    const Line line = next_line(("$End" + section).c_str());
    if (line.tokens.front() != "$End" + section) {
      fail(line.number, fmt::format("expected $End{}, got '{}'", section, line.tokens.front()));
    }
  }

  void skip_section(const std::string& section, int start) {
    const std::string end = "$End" + section;
    while (next_ < lines_.size()) {
      if (detail::trim(lines_[next_++]) == end) return;
    }
    fail(start, fmt::format("section ${} has no {}", section, end));
  }

  // $MeshFormat: "version file-type data-size"; file-type 0 = ASCII, 1 = binary.
  void read_format() {
    const Line line = next_line("'version file-type data-size'", 3);
    if (line.tokens[1] != "0") {
      fail(line.number, "binary MSH files are not supported; save as ASCII (Mesh.Binary = 0)");
    }
    if (line.tokens[0] != "4.1") {
      fail(line.number, fmt::format("MSH version {} is not supported; save as version 4.1 "
                                    "(Mesh.MshFileVersion = 4.1, or gmsh -format msh41)",
                                    line.tokens[0]));
    }
  }

  // $PhysicalNames: count, then "dimension physicalTag "name"" per line.
  void read_physical_names() {
    const std::size_t n = count(next_line("the number of physical names", 1), 0, "$PhysicalNames");
    for (std::size_t i = 0; i < n; ++i) {
      const Line line = next_line("'dimension tag \"name\"'", 3, true);
      const int dim = small_integer(line, 0, "physical dimension");
      const int tag = small_integer(line, 1, "physical tag");
      const std::string_view text = lines_[static_cast<std::size_t>(line.number - 1)];
      const std::size_t open = text.find('"');
      const std::size_t close = text.rfind('"');
      if (open == std::string_view::npos || close == open) {
        fail(line.number, "physical name must be in double quotes");
      }
      physical_names_[{dim, tag}] = std::string(text.substr(open + 1, close - open - 1));
    }
  }

  // $Entities: "numPoints numCurves numSurfaces numVolumes", then one line per entity:
  //   point:  tag x y z numPhysicalTags physicalTag...
  //   others: tag minX minY minZ maxX maxY maxZ numPhysicalTags physicalTag... numBounding ...
  void read_entities() {
    const Line header = next_line("the numbers of points, curves, surfaces and volumes", 4);
    for (int dim = 0; dim < 4; ++dim) {
      const std::size_t n = count(header, static_cast<std::size_t>(dim), "$Entities");
      const std::size_t first_physical = dim == 0 ? 4 : 7;
      for (std::size_t i = 0; i < n; ++i) {
        const Line line = next_line("an entity", first_physical + 1, true);
        const int tag = small_integer(line, 0, "entity tag");
        const std::size_t physicals = count(line, first_physical, "numPhysicalTags");
        if (line.tokens.size() < first_physical + 1 + physicals) {
          fail(line.number,
               fmt::format("entity {} lists fewer than its {} physical tags", tag, physicals));
        }
        std::vector<int>& groups = entity_physicals_[{dim, tag}];
        for (std::size_t p = 0; p < physicals; ++p) {
          // Gmsh may write a negative physical tag for a reversed orientation.
          groups.push_back(std::abs(small_integer(line, first_physical + 1 + p, "physical tag")));
        }
      }
    }
  }

  // $Nodes: "numEntityBlocks numNodes minNodeTag maxNodeTag", then per block
  // "entityDim entityTag parametric numNodesInBlock", its node tags (one per line), then their
  // coordinates "x y z [u [v [w]]]" (one per line).
  void read_nodes() {
    const Line header = next_line("'numEntityBlocks numNodes minNodeTag maxNodeTag'", 4);
    const std::size_t blocks = count(header, 0, "numEntityBlocks");
    const std::size_t declared = count(header, 1, "numNodes");
    std::size_t found = 0;
    for (std::size_t b = 0; b < blocks; ++b) {
      const Line block = next_line("'entityDim entityTag parametric numNodesInBlock'", 4);
      const std::size_t n = count(block, 3, "numNodesInBlock");
      found += n;
      std::vector<std::pair<long, int>> tags;  // tag, line
      for (std::size_t i = 0; i < n; ++i) {
        const Line line = next_line("a node tag", 1);
        tags.emplace_back(integer(line, 0, "node tag"), line.number);
      }
      for (const auto& [tag, tag_line] : tags) {
        const Line line = next_line("node coordinates 'x y z'", 3, true);
        if (const auto it = node_line_.find(tag); it != node_line_.end()) {
          fail(tag_line, fmt::format("node {} defined twice (first at line {})", tag, it->second));
        }
        node_line_[tag] = tag_line;
        node_index_[tag] = static_cast<int>(coordinates_.size());
        coordinates_.emplace_back(number(line, 0, "x"), number(line, 1, "y"), number(line, 2, "z"));
        node_tags_.push_back(tag);
      }
    }
    // A header that disagrees with its blocks means a truncated or hand-edited file: its nodes
    // may not be the ones the mesher wrote.
    if (found != declared)
      fail(header.number, fmt::format("the $Nodes header declares {} nodes, its {} blocks hold {}", declared, blocks, found));
  }

  // $Elements: "numEntityBlocks numElements minElementTag maxElementTag", then per block
  // "entityDim entityTag elementType numElementsInBlock" and one "tag node..." line per element.
  void read_elements() {
    const Line header = next_line("'numEntityBlocks numElements minElementTag maxElementTag'", 4);
    const std::size_t blocks = count(header, 0, "numEntityBlocks");
    const std::size_t declared = count(header, 1, "numElements");
    std::size_t found = 0;
    for (std::size_t b = 0; b < blocks; ++b) {
      const Line line = next_line("'entityDim entityTag elementType numElementsInBlock'", 4);
      ElementBlock block;
      block.line = line.number;
      block.dim = small_integer(line, 0, "entityDim");
      block.entity = small_integer(line, 1, "entityTag");
      block.type = small_integer(line, 2, "elementType");
      const std::size_t n = count(line, 3, "numElementsInBlock");
      for (std::size_t i = 0; i < n; ++i) {
        const Line element_line = next_line("an element 'tag node...'", 2, true);
        RawElement element;
        element.line = element_line.number;
        element.tag = integer(element_line, 0, "element tag");
        for (std::size_t k = 1; k < element_line.tokens.size(); ++k) {
          element.nodes.push_back(integer(element_line, k, "node tag"));
        }
        block.elements.push_back(std::move(element));
      }
      found += block.elements.size();
      blocks_.push_back(std::move(block));
    }
    if (found != declared)
      fail(header.number, fmt::format("the $Elements header declares {} elements, its {} blocks hold {}", declared, blocks, found));
  }

  std::string physical_name(int dim, int tag) const {
    const auto it = physical_names_.find({dim, tag});
    if (it != physical_names_.end()) return it->second;
    return fmt::format("{}_{}", dim == 3 ? "volume" : "surface", tag);
  }

  const std::vector<int>& physicals(int dim, int entity) const {
    static const std::vector<int> none;
    const auto it = entity_physicals_.find({dim, entity});
    return it == entity_physicals_.end() ? none : it->second;
  }

  int node_index(const RawElement& element, long tag) const {
    const auto it = node_index_.find(tag);
    if (it == node_index_.end()) {
      fail(element.line, fmt::format("element {}: unknown node {}", element.tag, tag));
    }
    return it->second;
  }

  void check_node_count(const ElementBlock& block, const RawElement& element,
                        std::size_t expected) const {
    if (element.nodes.size() != expected) {
      fail(element.line, fmt::format("element {} ({}) has {} nodes", element.tag,
                                     type_name(block.type), element.nodes.size()));
    }
  }

  int part_index(Mesh& mesh, const std::string& name) const {
    const auto it = std::find(mesh.parts.begin(), mesh.parts.end(), name);
    if (it != mesh.parts.end()) return static_cast<int>(it - mesh.parts.begin());
    mesh.parts.push_back(name);
    return static_cast<int>(mesh.parts.size()) - 1;
  }

  void add_volume_elements(Mesh& mesh, const ElementBlock& block,
                           std::unordered_map<long, int>& element_line) const {
    const std::optional<VolumeType> other = other_volume_type(block.type);
    if (block.type != kHex8 && block.type != kHex20 && !other) {
      std::string hint;
      if (block.type == 12 || block.type == 13)
        hint = "; for 20-node hexahedra and 15-node prisms set Mesh.SecondOrderIncomplete = 1";
      fail(block.line, fmt::format("element {} in volume {} is not supported: only hexahedra "
                                   "(type 5, 8 nodes; type 17, 20 nodes), tetrahedra (type 4, 4 "
                                   "nodes; type 11, 10 nodes) and prisms (type 6, 6 nodes; type "
                                   "18, 15 nodes){}",
                                   type_name(block.type), block.entity, hint));
    }
    const std::vector<int>& groups = physicals(3, block.entity);
    if (groups.size() > 1) {
      fail(block.line,
           fmt::format("volume {} is in the physical volumes '{}' and '{}': an "
                       "element can belong to one part only",
                       block.entity, physical_name(3, groups[0]), physical_name(3, groups[1])));
    }
    const std::string part = groups.empty() ? "default" : physical_name(3, groups.front());
    const int part_id = part_index(mesh, part);
    std::vector<int>& set = mesh.element_sets[part];
    const bool quadratic = block.type == kHex20;
    const ElementType type =
        other ? other->type : quadratic ? options_.hex20_type : options_.hex8_type;
    for (const RawElement& raw : block.elements) {
      check_node_count(block, raw, static_cast<std::size_t>(node_count(type)));
      if (const auto [it, fresh] = element_line.emplace(raw.tag, raw.line); !fresh) {
        fail(raw.line,
             fmt::format("element {} defined twice (first at line {})", raw.tag, it->second));
      }
      Element element;
      element.type = type;
      element.part = part_id;
      for (std::size_t a = 0; a < raw.nodes.size(); ++a) {
        std::size_t gmsh = a;
        if (quadratic) gmsh = static_cast<std::size_t>(kGmshOfAbaqus[a]);
        if (other && other->gmsh_of_abaqus) gmsh = static_cast<std::size_t>(other->gmsh_of_abaqus[a]);
        element.nodes[a] = node_index(raw, raw.nodes[gmsh]);
      }
      set.push_back(mesh.num_elements());
      mesh.elements.push_back(element);
      mesh.element_ids.push_back(raw.tag);
    }
  }

  using FaceKey = std::array<int, 4>;  // sorted corner nodes; -1 first for a triangle

  static FaceKey face_key(const std::vector<int>& corners) {
    FaceKey key = {-1, -1, -1, -1};
    std::copy(corners.begin(), corners.end(), key.begin());
    std::sort(key.begin(), key.end());
    return key;
  }

  static std::map<FaceKey, std::vector<Face>> faces_by_corners(const Mesh& mesh) {
    std::map<FaceKey, std::vector<Face>> faces;
    for (int e = 0; e < mesh.num_elements(); ++e) {
      const ElementType type = mesh.elements[static_cast<std::size_t>(e)].type;
      for (int f = 0; f < face_count(type); ++f) {
        std::vector<int> corners = face_nodes(mesh, {e, f});
        corners.resize(static_cast<std::size_t>(face_corner_count(type, f)));
        faces[face_key(corners)].push_back({e, f});
      }
    }
    return faces;
  }

  void add_surface_elements(Mesh& mesh, const ElementBlock& block,
                            const std::map<FaceKey, std::vector<Face>>& faces) const {
    const std::vector<int>& groups = physicals(2, block.entity);
    if (groups.empty()) return;
    const bool quadrangle = block.type == kQuad4 || block.type == kQuad8;
    const bool triangle = block.type == kTri3 || block.type == kTri6;
    if (!quadrangle && !triangle) {
      fail(block.line, fmt::format("element {} in physical surface '{}' is not supported: "
                                   "surfaces are made of quadrangles (type 3 or 16) or triangles "
                                   "(type 2 or 9) on element faces",
                                   type_name(block.type), physical_name(2, groups.front())));
    }
    const char* shape = quadrangle ? "quadrangle" : "triangle";
    const std::size_t corners = quadrangle ? 4 : 3;
    const bool quadratic = block.type == kQuad8 || block.type == kTri6;
    for (const RawElement& raw : block.elements) {
      check_node_count(block, raw, quadratic ? 2 * corners : corners);
      std::vector<int> corner_nodes;
      for (std::size_t a = 0; a < corners; ++a) corner_nodes.push_back(node_index(raw, raw.nodes[a]));
      const auto it = faces.find(face_key(corner_nodes));
      const std::string surface = physical_name(2, groups.front());
      if (it == faces.end()) {
        fail(raw.line, fmt::format("{} {} of physical surface '{}' is not a face of any "
                                   "volume element",
                                   shape, raw.tag, surface));
      }
      if (it->second.size() > 1) {
        fail(raw.line,
             fmt::format("{} {} of physical surface '{}' is a face of two "
                         "elements ({} and {}): a surface must lie on the boundary",
                         shape,
                         raw.tag, surface,
                         mesh.element_ids[static_cast<std::size_t>(it->second[0].element)],
                         mesh.element_ids[static_cast<std::size_t>(it->second[1].element)]));
      }
      for (int group : groups) {
        const std::string name = physical_name(2, group);
        auto& surface_faces = mesh.surfaces[name];
        if (std::find(surface_faces.begin(), surface_faces.end(), it->second.front()) ==
            surface_faces.end()) {
          surface_faces.push_back(it->second.front());
        }
        auto& nodes = mesh.node_sets[name];
        for (long tag : raw.nodes) nodes.push_back(node_index(raw, tag));
      }
    }
  }

  Mesh build() const {
    Mesh mesh;
    mesh.coordinates.resize(3, static_cast<Eigen::Index>(coordinates_.size()));
    for (std::size_t n = 0; n < coordinates_.size(); ++n) {
      mesh.coordinates.col(static_cast<Eigen::Index>(n)) = coordinates_[n];
    }
    mesh.node_ids = node_tags_;
    std::unordered_map<long, int> element_line;
    for (const ElementBlock& block : blocks_) {
      if (block.dim == 3) add_volume_elements(mesh, block, element_line);
    }
    if (mesh.elements.empty()) fail(0, "no volume elements: the file has no hexahedra, tetrahedra or prisms");
    const auto faces = faces_by_corners(mesh);
    for (const ElementBlock& block : blocks_) {
      if (block.dim == 2) add_surface_elements(mesh, block, faces);
    }
    for (auto& [name, nodes] : mesh.node_sets) {
      std::sort(nodes.begin(), nodes.end());
      nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    }
    return mesh;
  }

  std::string file_;
  std::vector<std::string_view> lines_;
  std::size_t next_ = 0;
  GmshOptions options_;
  std::map<std::pair<int, int>, std::string> physical_names_;         // (dim, tag) -> name
  std::map<std::pair<int, int>, std::vector<int>> entity_physicals_;  // (dim, entity) -> tags
  std::vector<Eigen::Vector3d> coordinates_;
  std::vector<long> node_tags_;
  std::unordered_map<long, int> node_index_;
  std::unordered_map<long, int> node_line_;
  std::vector<ElementBlock> blocks_;
};

}  // namespace

Mesh parse_gmsh(std::string_view text, const std::string& file_name, const GmshOptions& options) {
  if (const std::string message = options.validate(); !message.empty()) {
    throw std::invalid_argument("read_gmsh: " + message);
  }
  return GmshReader(file_name, text, options).read();
}

Mesh read_gmsh(const std::filesystem::path& file, const GmshOptions& options) {
  const std::string text = detail::read_file(file);
  return parse_gmsh(text, file.string(), options);
}

}  // namespace jointhb::fe
