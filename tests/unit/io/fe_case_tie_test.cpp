// Ties in an FE case (io/fe_case.hpp, docs/ties.md): a deck's *TIE between two instances of an
// assembly and the same tie written in the case (`model.ties`) give the same model (the same stage
// key, the same frequencies), near those of the uncut bar; a tie joins the parts it bonds for the
// connectivity check; bad ties stop with one line naming the file, the line and the key.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "jointhb/fe/box_mesh.hpp"
#include "jointhb/io/fe_case.hpp"
#include "jointhb/io/input_error.hpp"
#include "jointhb/pipeline/fe_pipeline.hpp"
#include "unit/io/temp_file.hpp"

namespace jointhb::io {
namespace {

namespace fs = std::filesystem;

using testing::CaseDir;

// A steel part BAR, 0.05 × 0.02 × 0.01 m of 5 × 2 × 1 C3D8I (`whole`: 0.1 m of 10 × 2 × 1), with
// surfaces LEFT (x = 0) and RIGHT and node set ROOT (x = 0), as the *PART of a deck.
std::string bar_part(bool whole) {
  fe::BoxOptions o;
  o.size = {whole ? 0.1 : 0.05, 0.02, 0.01};
  o.divisions = {whole ? 10 : 5, 2, 1};
  const fe::Mesh box = fe::box_mesh(o);
  std::string text = "*PART, NAME=BAR\n*NODE\n";
  for (int n = 0; n < box.num_nodes(); ++n)
    text += fmt::format("{}, {:.17g}, {:.17g}, {:.17g}\n", n + 1, box.coordinates(0, n), box.coordinates(1, n), box.coordinates(2, n));
  text += "*ELEMENT, TYPE=C3D8I, ELSET=BAR\n";
  for (int e = 0; e < box.num_elements(); ++e) {
    text += std::to_string(e + 1);
    for (int n : box.elements[static_cast<std::size_t>(e)].node_span()) text += ", " + std::to_string(n + 1);
    text += "\n";
  }
  text += "*NSET, NSET=ROOT\n";
  for (int n : box.node_sets.at("box.xmin")) text += std::to_string(n + 1) + ",\n";
  for (const auto& [name, side] : {std::pair{"LEFT", "box.xmin"}, std::pair{"RIGHT", "box.xmax"}}) {
    text += fmt::format("*SURFACE, NAME={}, TYPE=ELEMENT\n", name);
    for (const fe::Face& f : box.surfaces.at(side)) text += fmt::format("{}, S{}\n", f.element + 1, f.face + 1);
  }
  text += "*SOLID SECTION, ELSET=BAR, MATERIAL=STEEL\n*END PART\n";
  return text;
}

const char* const kMaterial = "*MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850.\n";

// Two instances H1 (x ∈ [0, 0.05]) and H2 (x ∈ [0.05, 0.1]) of the half bar, `tie` after the
// instances, H1.ROOT clamped when `clamp`.
std::string tied_deck(const std::string& tie, bool clamp) {
  std::string text = "*HEADING\ntied bar\n" + bar_part(false);
  text += "*ASSEMBLY, NAME=A\n*INSTANCE, NAME=H1, PART=BAR\n*END INSTANCE\n";
  text += "*INSTANCE, NAME=H2, PART=BAR\n0.05, 0., 0.\n*END INSTANCE\n" + tie + "*END ASSEMBLY\n";
  text += kMaterial;
  if (clamp) text += "*STEP\n*STATIC\n*BOUNDARY\nH1.ROOT, ENCASTRE\n*END STEP\n";
  return text;
}

// The 1-based line of the first line of `text` that starts with `start`.
int line_of(const std::string& text, const std::string& start) {
  int line = 1;
  for (std::size_t at = 0; at < text.size(); at = text.find('\n', at) + 1, ++line)
    if (text.compare(at, start.size(), start) == 0) return line;
  return 0;
}

const std::string kGlue = "*TIE, NAME=GLUE, ADJUST=YES, POSITION TOLERANCE=1e-4\nH2.LEFT, H1.RIGHT\n";

std::string case_text(const std::string& mesh, const std::string& extra = "") {
  return fmt::format("model:\n  type: fe\n  parts:\n    - {{mesh: {}}}\n{}analysis:\n  modes: {{count: 6, shift_hz: -1.0}}\n",
                     mesh, extra);
}

TEST(FeCaseTie, DeckTieAndCaseFileTieGiveTheSameModel) {
  const CaseDir d;
  d.write("tied.inp", tied_deck(kGlue, true));
  d.write("cut.inp", tied_deck("", true));
  d.write("whole.inp", "*HEADING\nwhole bar\n" + bar_part(true) +
                           "*ASSEMBLY, NAME=A\n*INSTANCE, NAME=W, PART=BAR\n*END INSTANCE\n*END ASSEMBLY\n" + kMaterial +
                           "*BOUNDARY\nW.ROOT, ENCASTRE\n");
  const FeCase by_deck = d.read(case_text("tied.inp"));
  const FeCase by_case = d.read(case_text("cut.inp", "  ties: [{name: GLUE, slave: H2.LEFT, master: H1.RIGHT}]\n"));
  const FeCase whole = d.read(case_text("whole.inp"));
  ASSERT_EQ(by_deck.ties.size(), 1u);
  EXPECT_EQ(by_deck.ties[0].slave_surface, "H2.LEFT");
  EXPECT_EQ(by_deck.ties[0].master_surface, "H1.RIGHT");
  EXPECT_EQ(by_deck.tie_sources[0], fmt::format("{}:{}", (d.dir / "tied.inp").string(), line_of(tied_deck(kGlue, true), "*TIE")));
  EXPECT_EQ(by_case.tie_sources[0], "model.ties[0]");
  EXPECT_EQ(by_deck.ties[0].num_tied_points(), 8);
  EXPECT_NEAR(by_deck.ties[0].area, 2e-4, 1e-18);

  pipeline::FePipeline a(by_deck, by_deck), b(by_case, by_case), w(whole, whole);
  // The same typed model: the same key (names do not enter it), and a key of its own against the
  // untied model, whose key has no tie part.
  EXPECT_EQ(a.keys().model, b.keys().model);
  FeCase untied = by_case;
  untied.ties.clear();
  EXPECT_NE(pipeline::fe_stage_keys(untied, untied).model, a.keys().model);
  const modal::ModalResult& ma = a.modes();
  const modal::ModalResult& mb = b.modes();
  const modal::ModalResult& mw = w.modes();
  ASSERT_EQ(ma.frequencies_hz.size(), 6);
  EXPECT_LT((ma.frequencies_hz - mb.frequencies_hz).cwiseAbs().maxCoeff(), 1e-10 * mb.frequencies_hz.maxCoeff());
  // Against the uncut bar: the tie's O(1/α) compliance at α = 1e3 (docs/ties.md §4).
  EXPECT_LT((ma.frequencies_hz.array() / mw.frequencies_hz.array() - 1.0).abs().maxCoeff(), 1e-3)
      << ma.frequencies_hz.transpose() << "\n" << mw.frequencies_hz.transpose();
  // A smaller penalty factor in the case loosens the bond.
  const FeCase loose = d.read(case_text("cut.inp", "  ties: [{name: GLUE, slave: H2.LEFT, master: H1.RIGHT, penalty_factor: 10}]\n"));
  EXPECT_EQ(loose.ties[0].penalty, by_case.ties[0].penalty / 100.0);
  pipeline::FePipeline l(loose, loose);
  EXPECT_LT(l.modes().frequencies_hz[0], mb.frequencies_hz[0] * (1.0 - 1e-4));
}

TEST(FeCaseTie, ATieConnectsAFreeFreeAssembly) {
  const CaseDir d;
  d.write("tied.inp", tied_deck(kGlue, false));
  d.write("cut.inp", tied_deck("", false));
  // Without the tie the two instances are separate bodies: refused when the case is read.
  EXPECT_NE(d.error(case_text("cut.inp")).find("part 'H2.BAR' is neither connected to part 'H1.BAR' (by an interface, a tie or a bolt)"),
            std::string::npos)
      << d.error(case_text("cut.inp"));
  const FeCase c = d.read(case_text("tied.inp"));
  pipeline::FePipeline p(c, c);
  const modal::ModalResult& m = p.modes();
  ASSERT_EQ(m.frequencies_hz.size(), 6);
  EXPECT_LT(m.frequencies_hz.cwiseAbs().maxCoeff(), 1.0) << m.frequencies_hz.transpose();  // six rigid-body modes
}

TEST(FeCaseTie, BadTiesAreOneLineErrors) {
  const CaseDir d;
  d.write("cut.inp", tied_deck("", true));
  const auto tie = [&](const std::string& entry) { return case_text("cut.inp", "  ties: [" + entry + "]\n"); };
  const std::string yaml = (d.dir / "case.yaml").string();
  EXPECT_EQ(d.error(tie("{slave: H2.LEFT, master: H1.RIGHTT}")).rfind(yaml + ":5:35: key 'model.ties[0].master': unknown surface 'H1.RIGHTT'; defined: ", 0), 0u)
      << d.error(tie("{slave: H2.LEFT, master: H1.RIGHTT}"));
  EXPECT_EQ(d.error(tie("{slave: H2.LEFT}")), yaml + ":5:10: key 'model.ties[0].master': required");
  EXPECT_NE(d.error(tie("{slave: H2.LEFT, master: H1.RIGHT, penalty: 1}")).find("key 'model.ties[0].penalty': unknown key; allowed: master, name, penalty_factor, slave"),
            std::string::npos);
  EXPECT_NE(d.error(tie("{slave: H2.LEFT, master: H1.RIGHT, penalty_factor: 0.5}")).find("key 'model.ties[0].penalty_factor': must be in [1, 1e6], got 0.5"),
            std::string::npos);
  EXPECT_NE(d.error(tie("{slave: H2.LEFT, master: H2.LEFT}")).find("key 'model.ties[0].master': must differ from slave"), std::string::npos);
  // Surfaces that do not face each other: the tie's own error, at the entry.
  EXPECT_NE(d.error(tie("{name: T, slave: H2.RIGHT, master: H1.LEFT}")).find(":5:10: key 'model.ties[0]': tie 'T' (slave = bottom, master = top): "),
            std::string::npos)
      << d.error(tie("{name: T, slave: H2.RIGHT, master: H1.LEFT}"));
  EXPECT_NE(d.error(tie("{name: T, slave: H2.LEFT, master: H1.RIGHT}, {name: T, slave: H1.RIGHT, master: H2.LEFT}"))
                .find("key 'model.ties[1].name': tie 'T' is defined twice (also at model.ties[0])"),
            std::string::npos);

  // In a deck: the deck's file and the *TIE's line, the part's key.
  const int tie_line = line_of(tied_deck(kGlue, true), "*TIE");
  d.write("bad.inp", tied_deck("*TIE, NAME=BAD\nH2.RIGHT, H1.LEFT\n", true));
  const std::string message = d.error(case_text("bad.inp"));
  EXPECT_EQ(message.rfind(fmt::format("{}:{}:1: key 'model.parts[0].mesh': tie 'BAD' (slave = bottom, master = top): ",
                                      (d.dir / "bad.inp").string(), tie_line), 0), 0u)
      << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
  d.write("bad.inp", tied_deck("*TIE, NAME=BAD\nH2.LEFT, H1.NOPE\n", true));
  EXPECT_EQ(d.error(case_text("bad.inp")),
            fmt::format("{}:{}:1: key 'model.parts[0].mesh': *TIE 'BAD': unknown master surface 'H1.NOPE'",
                        (d.dir / "bad.inp").string(), tie_line + 1));
  d.write("tied.inp", tied_deck(kGlue, true));
  EXPECT_NE(d.error(case_text("tied.inp", "  ties: [{name: GLUE, slave: H1.RIGHT, master: H2.LEFT}]\n"))
                .find(fmt::format("tie 'GLUE' is defined twice (also at {}:{})", (d.dir / "tied.inp").string(), tie_line)),
            std::string::npos);
}

}  // namespace
}  // namespace jointhb::io
