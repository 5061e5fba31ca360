// The stage cache (io/stage_cache.hpp): bit-identical round trips of the cached stage results, a
// damaged or foreign file is a miss (never a crash), a file whose records differ from this build's
// fields (or of format version 1) is a miss naming the field, a cache that cannot be written is a
// warning, the member count behind the compile-time field checks, and the FE stage keys
// (pipeline::fe_stage_keys of a case) change exactly when their inputs change.
#include "jointhb/io/stage_cache.hpp"
#include "jointhb/pipeline/fe_model.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <string>

#include "jointhb/contact/jenkins_law.hpp"
#include "jointhb/fe/assembly.hpp"
#include "jointhb/io/aggregate_field_count.hpp"
#include "jointhb/io/fe_case.hpp"

namespace io = jointhb::io;
namespace pl = jointhb::preload;
namespace modal = jointhb::modal;
namespace fs = std::filesystem;

namespace {

// A directory in the system temp directory, unique to this process and test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() / ("jointhb-" + std::to_string(::getpid()) + "-" +
                                         info->test_suite_name() + "-" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::string read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void write_bytes(const fs::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
}

bool same_bits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         (a.size() == 0 || std::memcmp(a.data(), b.data(), static_cast<std::size_t>(a.size()) * sizeof(double)) == 0);
}

// The coarse lap of cases/05 (10 mm elements, Jenkins contact), with `analysis` appended.
std::string lap_yaml(const std::string& analysis) {
  return R"(# two plates and two bolts
model:
  type: fe
  materials:
    aluminium: {youngs_modulus: 70.0e9, poissons_ratio: 0.33, density: 2700.0}
  parts:
    - {name: lower, material: aluminium, element: C3D8I,
       box: {origin: [0.0, 0.0, 0.0], size: [0.100, 0.030, 0.004], divisions: [10, 3, 2]}}
    - {name: upper, material: aluminium, element: C3D8I,
       box: {origin: [0.060, 0.0, 0.004], size: [0.100, 0.030, 0.004], divisions: [10, 3, 2]}}
  interfaces:
    - name: lap
      bottom: lower.zmax
      top: upper.zmin
      region: {min: [0.060, 0.0, 0.0039], max: [0.100, 0.030, 0.0041]}
      integration: nodal
      contact: {pressure: 1.0e6, decay: 1.0e6, mu: 0.3, law: jenkins, stiffness_ratio: 0.8}
  bolts:
    - {name: bolt-1, point: [0.070, 0.015, 0.0], direction: [0.0, 0.0, 1.0],
       head: {surface: upper.zmax, radius: 0.006}, nut: {surface: lower.zmin, radius: 0.006},
       stiffness: 5.0e8, preload: 5000.0}
    - {name: bolt-2, point: [0.090, 0.015, 0.0], direction: [0.0, 0.0, 1.0],
       head: {surface: upper.zmax, radius: 0.006}, nut: {surface: lower.zmin, radius: 0.006},
       stiffness: 5.0e8, preload: 5000.0}
)" + analysis;
}

const char* const kAnalysis = R"(analysis:
  preload: {load_steps: 4, tolerance: 1.0e-9}
  modes: {count: 10, shift_hz: -10.0}
)";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  if (at == std::string::npos) throw std::logic_error("no '" + from + "' in the text");
  return text.replace(at, from.size(), to);
}

jointhb::pipeline::FeStageKeys keys_of(const std::string& text) {
  const io::FeCase c = io::parse_fe_case(text, "lap.yaml");
  return jointhb::pipeline::fe_stage_keys(c, c);
}

const pl::PreloadResult& lap_preload() {
  static const pl::PreloadResult result = [] {
    const io::FeCase c = io::parse_fe_case(lap_yaml(kAnalysis), "lap.yaml");
    pl::PreloadModel model;
    model.mesh = &c.mesh;
    model.structure = jointhb::fe::assemble(c.mesh, c.material_per_part);
    model.interfaces = c.interfaces;
    model.bolts = c.bolts;
    return pl::solve_preload(model, c.preload);
  }();
  return result;
}

modal::ModalResult hand_made_modes() {
  modal::ModalResult m;
  m.termination = jointhb::Termination::no_convergence;
  m.message = "2 of 3 modes converged";
  m.eigenvalues = Eigen::Vector3d(-0.0, 1.0e-300, std::numbers::pi * 1e6);
  m.frequencies_hz = Eigen::Vector3d(-std::numeric_limits<double>::denorm_min(), 1.0, 159.0);
  m.shapes = Eigen::MatrixXd::Random(7, 3);
  m.residuals = Eigen::Vector3d(1e-12, 2e-13, 3e-14);
  m.backward_errors = Eigen::Vector3d(1e-17, 2e-17, 3e-17);
  m.shift = -39.47841760435743;
  m.requested = 3;
  m.iterations = 5;
  m.operator_applications = 41;
  m.mass_applications = 43;
  m.ncv = 6;
  m.factor.rows = 7;
  m.factor.matrix_nonzeros = 19;
  m.factor.factor_nonzeros = 22.0;
  m.factor.factor_entries = 25;
  m.factor.factor_flops = 123.5;
  m.factor.ordering = "AMD";
  m.factor.factorizations = 1;
  m.factor.analyze_seconds = 0.001;
  m.factor.factorize_seconds = 0.002;
  m.factor_seconds = 0.003;
  m.lanczos_seconds = 0.004;
  m.seconds = 0.0071;
  return m;
}

void expect_same(const modal::ModalResult& a, const modal::ModalResult& b) {
  EXPECT_EQ(a.termination, b.termination);
  EXPECT_EQ(a.message, b.message);
  EXPECT_TRUE(same_bits(a.eigenvalues, b.eigenvalues));
  EXPECT_TRUE(same_bits(a.frequencies_hz, b.frequencies_hz));
  EXPECT_TRUE(same_bits(a.shapes, b.shapes));
  EXPECT_TRUE(same_bits(a.residuals, b.residuals));
  EXPECT_TRUE(same_bits(a.backward_errors, b.backward_errors));
  EXPECT_EQ(a.shift, b.shift);
  EXPECT_EQ(a.requested, b.requested);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.operator_applications, b.operator_applications);
  EXPECT_EQ(a.mass_applications, b.mass_applications);
  EXPECT_EQ(a.ncv, b.ncv);
  EXPECT_EQ(a.factor.ordering, b.factor.ordering);
  EXPECT_EQ(a.factor.factor_flops, b.factor.factor_flops);
  EXPECT_EQ(a.factor.factorizations, b.factor.factorizations);
  EXPECT_EQ(a.seconds, b.seconds);
  EXPECT_EQ(io::encode_modes(a), io::encode_modes(b));
}


// ---- the file format, written from its description in stage_cache.hpp --------------------------
// An independent reader and writer of records, so that the tests can remove, rename, add and
// retype fields of a real payload and write a file with a valid header and checksum around it.

std::uint64_t le(std::string_view b, std::size_t at, int bytes) {
  std::uint64_t v = 0;
  for (int k = 0; k < bytes; ++k) v |= static_cast<std::uint64_t>(static_cast<unsigned char>(b.at(at + k))) << (8 * k);
  return v;
}
void put_le(std::string& out, std::uint64_t v, int bytes) {
  for (int k = 0; k < bytes; ++k) out.push_back(static_cast<char>((v >> (8 * k)) & 0xffU));
}
void put_str(std::string& out, std::string_view s) {
  put_le(out, s.size(), 8);
  out.append(s);
}

struct RawField {
  std::string name;
  std::uint8_t code = 0;
  std::string bytes;
};
struct RawRecord {
  std::string type;
  std::vector<RawField> fields;

  RawField& field(const std::string& name) {
    for (auto& f : fields)
      if (f.name == name) return f;
    throw std::logic_error("no field " + name);
  }
  void erase(const std::string& name) {
    const auto before = fields.size();
    std::erase_if(fields, [&](const RawField& f) { return f.name == name; });
    if (fields.size() != before - 1) throw std::logic_error("no field " + name);
  }
};

RawRecord parse_record(std::string_view b) {
  std::size_t at = 0;
  const auto str = [&] {
    const auto n = static_cast<std::size_t>(le(b, at, 8));
    std::string s(b.substr(at + 8, n));
    at += 8 + n;
    return s;
  };
  RawRecord r;
  r.type = str();
  const auto count = le(b, at, 4);
  at += 4;
  for (std::uint64_t k = 0; k < count; ++k) {
    RawField f;
    f.name = str();
    f.code = static_cast<std::uint8_t>(b.at(at));
    ++at;
    const auto n = static_cast<std::size_t>(le(b, at, 8));
    f.bytes = std::string(b.substr(at + 8, n));
    at += 8 + n;
    r.fields.push_back(f);
  }
  if (at != b.size()) throw std::logic_error("trailing bytes after the record");
  return r;
}

std::string emit(const RawRecord& r) {
  std::string out;
  put_str(out, r.type);
  put_le(out, r.fields.size(), 4);
  for (const auto& f : r.fields) {
    put_str(out, f.name);
    out.push_back(static_cast<char>(f.code));
    put_str(out, f.bytes);
  }
  return out;
}

std::uint64_t fnv1a64(std::string_view bytes) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

/// A cache file with a correct header and checksum around `payload`.
void write_cache_file(const fs::path& file, std::string_view stage, std::string_view key, const std::string& payload,
                      std::uint32_t version = io::stage_cache_format) {
  std::string out = "JHBC";
  put_le(out, version, 4);
  put_str(out, stage);
  put_str(out, key);
  put_str(out, payload);
  put_le(out, fnv1a64(payload), 8);
  write_bytes(file, out);
}

/// A small preload result with every kind of field filled (no solve).
pl::PreloadResult hand_made_preload() {
  pl::PreloadResult p;
  p.termination = jointhb::Termination::converged;
  p.message = "";
  p.steps.push_back({0.5, 3, 2, 1, 0, 1e-10, jointhb::Termination::converged, ""});
  p.steps.push_back({1.0, 2, 1, 1, 1, 2e-11, jointhb::Termination::converged, ""});
  p.displacement = Eigen::VectorXd::Random(12);
  p.load_factor = 1.0;
  pl::InterfaceResult i;
  i.name = "lap";
  i.state.gap = Eigen::VectorXd::Random(6);
  i.state.traction = Eigen::VectorXd::Random(6);
  i.state.pressure = Eigen::VectorXd::Random(2);
  i.state.tangent = {Eigen::Matrix3d::Random(), Eigen::Matrix3d::Random()};
  i.state.open = {false, true};
  i.state.num_open = 1;
  i.state.force = Eigen::VectorXd::Random(12);
  i.state.stiffness = Eigen::MatrixXd::Identity(12, 12).sparseView();
  i.clamping_force = 1e4;
  i.min_gap = -1e-7;
  p.interfaces.push_back(i);
  p.bolt_forces = {5000.0, 5000.5};
  p.support_dofs = {0, 1, 2, 4, 5, 8};
  p.support_reaction = 1e-15;
  p.dofs.free_of_full = {0, -1, 1, 2};
  p.dofs.full_of_free = {0, 2, 3};
  p.dynamic_stiffness = Eigen::MatrixXd::Identity(12, 12).sparseView();
  p.factor_statistics = "n=12";
  p.factor.ordering = "AMD";
  p.factor.factorizations = 3;
  p.total_iterations = 5;
  p.seconds = 0.25;
  return p;
}
}  // namespace

// ---- Fingerprint ---------------------------------------------------------------------------------

TEST(Fingerprint, SameInputSameKeyAndOneDoubleChangesIt) {
  Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(50, 0.0, 1.0);
  const std::string a = io::Fingerprint().add("x").add(1.5).add(3).add(v).hex();
  EXPECT_EQ(a.size(), 32u);
  EXPECT_EQ(a, io::Fingerprint().add("x").add(1.5).add(3).add(v).hex());
  EXPECT_NE(a, io::Fingerprint().add("x").add(std::nextafter(1.5, 2.0)).add(3).add(v).hex());
  EXPECT_NE(io::Fingerprint().add(0.0).hex(), io::Fingerprint().add(-0.0).hex());
  Eigen::VectorXd w = v;
  w[17] = std::nextafter(w[17], 1.0);
  EXPECT_NE(a, io::Fingerprint().add("x").add(1.5).add(3).add(w).hex());
  EXPECT_NE(a, io::Fingerprint().add("x").add(1.5).add(4).add(v).hex());
  // Lengths and type tags separate the values.
  EXPECT_NE(io::Fingerprint().add("ab").add("c").hex(), io::Fingerprint().add("a").add("bc").hex());
  EXPECT_NE(io::Fingerprint().add(1).hex(), io::Fingerprint().add(1.0).hex());
  // A chained key depends on its parent.
  EXPECT_NE(io::Fingerprint::chain(a).add("m").hex(), io::Fingerprint::chain(a + "0").add("m").hex());
  EXPECT_EQ(io::Fingerprint::chain(a).add("m").hex(), io::Fingerprint::chain(a).add("m").hex());
}

TEST(Fingerprint, FileContents) {
  TempDir dir;
  write_bytes(dir.path() / "a.txt", "some mesh\n");
  const std::string k1 = io::Fingerprint().add_file(dir.path() / "a.txt").hex();
  write_bytes(dir.path() / "a.txt", "some mesh.\n");
  EXPECT_NE(k1, io::Fingerprint().add_file(dir.path() / "a.txt").hex());
  EXPECT_THROW(io::Fingerprint().add_file(dir.path() / "missing.txt"), std::runtime_error);
}

// ---- round trips ---------------------------------------------------------------------------------

TEST(StageCache, PreloadRoundTripIsBitIdentical) {
  const pl::PreloadResult& p = lap_preload();
  ASSERT_EQ(p.termination, jointhb::Termination::converged) << p.message;
  ASSERT_GT(p.dynamic_stiffness.nonZeros(), 0);
  ASSERT_EQ(p.interfaces.size(), 1u);
  TempDir dir;
  io::StageCache cache(dir.path() / "cache", true);
  EXPECT_FALSE(cache.load_preload("0123").has_value());
  cache.store_preload("0123", p);
  EXPECT_TRUE(fs::exists(dir.path() / "cache" / "preload-0123.bin"));
  const auto q = cache.load_preload("0123");
  ASSERT_TRUE(q.has_value());
  EXPECT_TRUE(cache.warnings().empty());
  EXPECT_EQ(q->termination, p.termination);
  EXPECT_EQ(q->message, p.message);
  ASSERT_EQ(q->steps.size(), p.steps.size());
  EXPECT_EQ(q->steps.back().iterations, p.steps.back().iterations);
  EXPECT_EQ(q->steps.back().residual, p.steps.back().residual);
  EXPECT_TRUE(same_bits(q->displacement, p.displacement));
  EXPECT_EQ(q->load_factor, p.load_factor);
  const auto& a = q->interfaces[0];
  const auto& b = p.interfaces[0];
  EXPECT_EQ(a.name, b.name);
  EXPECT_TRUE(same_bits(a.state.gap, b.state.gap));
  EXPECT_TRUE(same_bits(a.state.traction, b.state.traction));
  EXPECT_TRUE(same_bits(a.state.pressure, b.state.pressure));
  EXPECT_TRUE(same_bits(a.state.force, b.state.force));
  EXPECT_EQ(a.state.open, b.state.open);
  EXPECT_EQ(a.state.num_open, b.state.num_open);
  ASSERT_EQ(a.state.tangent.size(), b.state.tangent.size());
  EXPECT_TRUE(same_bits(a.state.tangent.back(), b.state.tangent.back()));
  EXPECT_EQ(a.clamping_force, b.clamping_force);
  EXPECT_EQ(a.closed_area_fraction, b.closed_area_fraction);
  EXPECT_EQ(a.min_gap, b.min_gap);
  EXPECT_EQ(q->bolt_forces, p.bolt_forces);
  EXPECT_EQ(q->support_dofs, p.support_dofs);
  EXPECT_EQ(q->support_reaction, p.support_reaction);
  EXPECT_EQ(q->dofs.free_of_full, p.dofs.free_of_full);
  EXPECT_EQ(q->dofs.full_of_free, p.dofs.full_of_free);
  ASSERT_EQ(q->dynamic_stiffness.nonZeros(), p.dynamic_stiffness.nonZeros());
  EXPECT_TRUE(same_bits(Eigen::MatrixXd(q->dynamic_stiffness), Eigen::MatrixXd(p.dynamic_stiffness)));
  EXPECT_EQ(q->factor_statistics, p.factor_statistics);
  EXPECT_EQ(q->factor.factorizations, p.factor.factorizations);
  EXPECT_EQ(q->factor.ordering, p.factor.ordering);
  EXPECT_EQ(q->total_iterations, p.total_iterations);
  EXPECT_EQ(q->seconds, p.seconds);
  EXPECT_EQ(q->contact_seconds, p.contact_seconds);
  // Every field: the encoding of the copy is the encoding of the original.
  EXPECT_EQ(io::encode_preload(*q), io::encode_preload(p));
}

TEST(StageCache, ModesRoundTripIsBitIdentical) {
  const modal::ModalResult m = hand_made_modes();
  TempDir dir;
  io::StageCache cache(dir.path(), true);
  cache.store_modes("k", m);
  const auto n = cache.load_modes("k");
  ASSERT_TRUE(n.has_value());
  expect_same(*n, m);
  EXPECT_TRUE(std::signbit(n->eigenvalues[0]));  // −0.0 kept
  // Another key, another file: a miss.
  EXPECT_FALSE(cache.load_modes("l").has_value());
  EXPECT_TRUE(cache.warnings().empty());
}

TEST(StageCache, FieldRecoveryRoundTripIsBitIdenticalAndChecked) {
  jointhb::reduction::FieldRecovery f;
  f.modes = Eigen::MatrixXd::Random(5, 2);
  f.residual = Eigen::MatrixXd::Random(5, 3);
  f.column_of_row = {0, 1, 2, 0, 1, 2};
  f.load_residual = Eigen::VectorXd::Random(5);
  f.full_of_free = {0, 1, 3, 4, 6};
  f.num_full = 9;
  f.rayleigh_stiffness = 1.25e-6;
  TempDir dir;
  io::StageCache cache(dir.path(), true);
  cache.store_field_recovery("k", f);
  const auto g = cache.load_field_recovery("k");
  ASSERT_TRUE(g.has_value());
  EXPECT_EQ(g->modes, f.modes);
  EXPECT_EQ(g->residual, f.residual);
  EXPECT_EQ(g->column_of_row, f.column_of_row);
  EXPECT_EQ(g->load_residual, f.load_residual);
  EXPECT_EQ(g->full_of_free, f.full_of_free);
  EXPECT_EQ(g->num_full, f.num_full);
  EXPECT_EQ(g->rayleigh_stiffness, f.rayleigh_stiffness);
  EXPECT_FALSE(cache.load_field_recovery("l").has_value());
  // a column or DOF out of range does not decode
  jointhb::reduction::FieldRecovery bad = f;
  bad.column_of_row[4] = 3;
  EXPECT_THROW((void)io::decode_field_recovery(io::encode_field_recovery(bad)), std::runtime_error);
  bad = f;
  bad.full_of_free[4] = 9;
  EXPECT_THROW((void)io::decode_field_recovery(io::encode_field_recovery(bad)), std::runtime_error);
}

TEST(StageCache, InterfaceModelRoundTripTakesTheLawsFromTheCaller) {
  const auto law = [](double mu) {
    jointhb::contact::ContactPointOptions o;
    o.friction_coefficient = mu;
    return jointhb::contact::ContactPoint(o, std::make_shared<jointhb::contact::JenkinsLaw>());
  };
  jointhb::hb::InterfaceModel m;
  m.omega2 = Eigen::Vector3d(0.0, 4.0e6, 9.0e6);
  m.rigid_modes = 1;
  m.gap_shapes = Eigen::MatrixXd::Random(9, 3);
  m.rayleigh_mass = 1.5;
  m.rayleigh_stiffness = 2e-6;
  m.residual_shift = -39.5;
  m.residual_flexibility = Eigen::MatrixXd::Random(9, 9);
  m.residual_inertia = Eigen::MatrixXd::Random(9, 9);
  m.groups.push_back({"a", law(0.3), 0, 2});
  m.groups.push_back({"b", law(0.2), 2, 1});
  for (int p = 0; p < 3; ++p) {
    jointhb::hb::ContactPointReference r;
    r.gap = Eigen::Vector3d::Random();
    r.traction = Eigen::Vector3d::Random();
    m.references.push_back(r);
    m.stuck_tangents.push_back(Eigen::Matrix3d::Random());
  }
  m.areas = Eigen::Vector3d(1e-6, 2e-6, 3e-6);
  m.load_name = "node 3 z";
  m.load_modal = Eigen::Vector3d::Random();
  m.load_residual0 = Eigen::VectorXd::Random(9);
  m.load_residual1 = Eigen::VectorXd::Random(9);
  m.outputs.push_back({"node 7 x", Eigen::Vector3d::Random(), Eigen::VectorXd::Random(9),
                       Eigen::VectorXd::Random(9), 0.25, -0.5});
  TempDir dir;
  io::StageCache cache(dir.path(), true);
  cache.store_interface_model("k", m);
  const auto n = cache.load_interface_model("k", {law(0.3), law(0.2)});
  ASSERT_TRUE(n.has_value());
  EXPECT_EQ(io::encode_interface_model(*n), io::encode_interface_model(m));
  ASSERT_EQ(n->groups.size(), 2u);
  EXPECT_EQ(n->groups[1].name, "b");
  EXPECT_EQ(n->groups[1].first, 2);
  EXPECT_EQ(n->groups[1].law.options().friction_coefficient, 0.2);
  EXPECT_TRUE(same_bits(n->residual_flexibility, m.residual_flexibility));
  EXPECT_TRUE(same_bits(n->stuck_tangents[2], m.stuck_tangents[2]));
  EXPECT_TRUE(cache.warnings().empty());
  // The wrong number of laws: a miss with a warning.
  EXPECT_FALSE(cache.load_interface_model("k", {law(0.3)}).has_value());
  EXPECT_EQ(cache.warnings().size(), 1u);
}

// ---- damaged files -------------------------------------------------------------------------------

TEST(StageCache, TruncatedFlippedAndWrongVersionFilesAreMisses) {
  const modal::ModalResult m = hand_made_modes();
  TempDir dir;
  io::StageCache cache(dir.path(), true);
  cache.store_modes("k", m);
  const fs::path file = cache.file("modes", "k");
  const std::string good = read_bytes(file);
  ASSERT_GT(good.size(), 100u);
  std::size_t warnings = 0;
  const auto expect_miss = [&](const std::string& bytes, const char* what) {
    write_bytes(file, bytes);
    EXPECT_FALSE(cache.load_modes("k").has_value()) << what;
    EXPECT_EQ(cache.warnings().size(), ++warnings) << what;
  };
  // Truncated anywhere (inside the header, the payload, the checksum), and empty.
  for (const std::size_t n : {std::size_t{0}, std::size_t{3}, std::size_t{10}, std::size_t{30}, good.size() / 2, good.size() - 1})
    expect_miss(good.substr(0, n), "truncated");
  expect_miss(good + "x", "trailing byte");
  // One flipped bit in every part of the file.
  for (const std::size_t at : {std::size_t{1}, std::size_t{12}, std::size_t{40}, good.size() / 2, good.size() - 3}) {
    std::string bad = good;
    bad[at] = static_cast<char>(bad[at] ^ 0x10);
    expect_miss(bad, "flipped");
  }
  // Another format version (bytes 4..7, little-endian).
  std::string other = good;
  other[4] = static_cast<char>(io::stage_cache_format + 1);
  expect_miss(other, "version");
  EXPECT_NE(cache.warnings().back().find("format version"), std::string::npos) << cache.warnings().back();
  // A file of another stage under this name.
  cache.store_preload("k", lap_preload());
  write_bytes(file, read_bytes(cache.file("preload", "k")));
  EXPECT_FALSE(cache.load_modes("k").has_value());
  // The good file again: a hit.
  write_bytes(file, good);
  ASSERT_TRUE(cache.load_modes("k").has_value());
  expect_same(*cache.load_modes("k"), m);
}

TEST(StageCache, DisabledAndUnwritableCachesDoNotStopTheRun) {
  const modal::ModalResult m = hand_made_modes();
  TempDir dir;
  io::StageCache off(dir.path() / "off", false);
  off.store_modes("k", m);
  EXPECT_FALSE(fs::exists(dir.path() / "off"));
  EXPECT_FALSE(off.load_modes("k").has_value());
  // A cache directory below a regular file cannot be created: a warning, no file, no throw.
  write_bytes(dir.path() / "file", "x");
  io::StageCache blocked(dir.path() / "file" / "cache", true);
  EXPECT_NO_THROW(blocked.store_modes("k", m));
  EXPECT_EQ(blocked.warnings().size(), 1u);
  EXPECT_FALSE(blocked.load_modes("k").has_value());
  // Decoding garbage throws (the cache turns that into a miss).
  EXPECT_THROW((void)io::decode_modes("garbage"), std::runtime_error);
  EXPECT_THROW((void)io::decode_preload(std::string(64, '\xff')), std::runtime_error);
}

// ---- records: fields by name ---------------------------------------------------------------------

TEST(StageCacheFormat, PayloadIsTheDocumentedRecord) {
  // The top-level record of the modes: type name, the members by their C++ names in order, and
  // the type codes of stage_cache.hpp. A parse -> emit round trip reproduces the payload exactly,
  // so the tampering tests below change only what they mean to.
  const std::string payload = io::encode_modes(hand_made_modes());
  const RawRecord r = parse_record(payload);
  EXPECT_EQ(r.type, "ModalResult");
  std::vector<std::string> names;
  for (const auto& f : r.fields) names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{"termination", "message", "eigenvalues", "frequencies_hz", "shapes",
                                             "residuals", "backward_errors", "shift", "requested", "iterations",
                                             "operator_applications", "mass_applications", "ncv", "factor",
                                             "factor_seconds", "lanczos_seconds", "seconds"}));
  RawRecord copy = r;
  EXPECT_EQ(copy.field("termination").code, 6);  // enumeration
  EXPECT_EQ(copy.field("message").code, 5);   // string
  EXPECT_EQ(copy.field("eigenvalues").code, 7);  // f64 array
  EXPECT_EQ(copy.field("eigenvalues").bytes.size(), 3 * sizeof(double));
  EXPECT_EQ(copy.field("shapes").code, 8);    // f64 matrix: rows, cols, values
  EXPECT_EQ(copy.field("shapes").bytes.size(), 16 + 7 * 3 * sizeof(double));
  EXPECT_EQ(copy.field("requested").code, 2);  // i32
  EXPECT_EQ(copy.field("shift").code, 4);      // f64
  EXPECT_EQ(copy.field("factor").code, 14);    // nested record
  EXPECT_EQ(parse_record(copy.field("factor").bytes).type, "SparseCholeskyStatistics");
  EXPECT_EQ(emit(r), payload);
}

TEST(StageCacheFormat, FieldSetMismatchThrowsNamingRecordAndFieldAndIsAMiss) {
  const pl::PreloadResult p = hand_made_preload();
  const std::string good = io::encode_preload(p);
  const RawRecord base = parse_record(good);
  ASSERT_EQ(emit(base), good);
  TempDir dir;
  io::StageCache cache(dir.path(), true);
  const fs::path file = cache.file("preload", "k");
  // The untouched record, rewritten by the test's writer: a hit (the cases below differ only in
  // what they change).
  write_cache_file(file, "preload", "k", emit(base));
  ASSERT_TRUE(cache.load_preload("k").has_value());
  ASSERT_TRUE(cache.warnings().empty());

  // Each case: decode_preload throws a runtime_error whose message holds every `expected` piece,
  // and load_preload is a miss with one warning naming the file and the field.
  const auto expect_mismatch = [&](const RawRecord& r, const std::vector<std::string>& expected, const char* what) {
    const std::string payload = emit(r);
    try {
      (void)io::decode_preload(payload);
      ADD_FAILURE() << what << ": decoded";
    } catch (const std::runtime_error& e) {
      for (const auto& piece : expected)
        EXPECT_NE(std::string(e.what()).find(piece), std::string::npos) << what << ": " << e.what();
    }
    const std::size_t before = cache.warnings().size();
    write_cache_file(file, "preload", "k", payload);
    EXPECT_FALSE(cache.load_preload("k").has_value()) << what;
    ASSERT_EQ(cache.warnings().size(), before + 1) << what;
    const std::string& warning = cache.warnings().back();
    EXPECT_NE(warning.find(file.string()), std::string::npos) << warning;
    for (const auto& piece : expected) EXPECT_NE(warning.find(piece), std::string::npos) << what << ": " << warning;
  };

  {
    RawRecord r = base;
    r.erase("bolt_forces");
    expect_mismatch(r, {"PreloadResult: field 'bolt_forces' missing"}, "removed");
  }
  {
    RawRecord r = base;
    r.field("bolt_forces").name = "bolt_force";
    expect_mismatch(r, {"PreloadResult: field 'bolt_forces' missing"}, "renamed");
  }
  {
    RawRecord r = base;
    r.fields.push_back({"bolt_torques", 7, std::string(16, '\0')});
    expect_mismatch(r, {"PreloadResult", "unknown field 'bolt_torques'"}, "extra");
  }
  {
    RawRecord r = base;
    r.field("bolt_forces").code = 9;  // i32 array instead of f64 array: same 16 bytes
    expect_mismatch(r, {"PreloadResult: field 'bolt_forces'", "type code 9"}, "retyped");
  }
  {
    RawRecord r = base;
    r.field("load_factor").bytes.resize(4);  // an f64 of 4 bytes
    expect_mismatch(r, {"PreloadResult: field 'load_factor'", "4 bytes"}, "wrong length");
  }
  {
    RawRecord r = base;
    r.type = "PreloadResult2";
    expect_mismatch(r, {"PreloadResult", "'PreloadResult2'"}, "record type");
  }
  {
    RawRecord r = base;
    RawRecord factor = parse_record(r.field("factor").bytes);
    factor.erase("ordering");
    r.field("factor").bytes = emit(factor);
    expect_mismatch(r, {"SparseCholeskyStatistics: field 'ordering' missing"}, "nested record");
  }
  {
    RawRecord r = base;
    r.fields.push_back(r.field("message"));
    expect_mismatch(r, {"PreloadResult: field 'message' appears twice"}, "duplicate");
  }
}

TEST(StageCacheFormat, EveryStageLoadNamesTheMismatchedField) {
  // The other three stages through their load_*: one mismatch each, in a nested record, a record
  // list and record columns.
  TempDir dir;
  io::StageCache cache(dir.path(), true);
  const auto expect_miss_naming = [&](const std::string& piece, const char* what) {
    ASSERT_FALSE(cache.warnings().empty()) << what;
    EXPECT_NE(cache.warnings().back().find(piece), std::string::npos) << what << ": " << cache.warnings().back();
  };
  {
    RawRecord r = parse_record(io::encode_modes(hand_made_modes()));
    RawRecord factor = parse_record(r.field("factor").bytes);
    factor.fields.push_back({"solve_seconds", 4, std::string(8, '\0')});
    r.field("factor").bytes = emit(factor);
    write_cache_file(cache.file("modes", "k"), "modes", "k", emit(r));
    EXPECT_FALSE(cache.load_modes("k").has_value());
    expect_miss_naming("SparseCholeskyStatistics: unknown field 'solve_seconds'", "modes");
  }
  {
    jointhb::reduction::FieldRecovery f;
    f.modes = Eigen::MatrixXd::Random(2, 1);
    f.residual = Eigen::MatrixXd::Random(2, 1);
    f.column_of_row = {0, 0, 0};
    f.load_residual = Eigen::VectorXd::Random(2);
    f.full_of_free = {0, 1};
    f.num_full = 3;
    RawRecord r = parse_record(io::encode_field_recovery(f));
    r.field("num_full").code = 3;  // i64 instead of i32
    r.field("num_full").bytes.resize(8, '\0');
    write_cache_file(cache.file("recovery", "k"), "recovery", "k", emit(r));
    EXPECT_FALSE(cache.load_field_recovery("k").has_value());
    expect_miss_naming("FieldRecovery: field 'num_full' has type code 3", "recovery");
  }
  {
    const auto law = [] {
      return jointhb::contact::ContactPoint(jointhb::contact::ContactPointOptions{},
                                            std::make_shared<jointhb::contact::JenkinsLaw>());
    };
    jointhb::hb::InterfaceModel m;
    m.omega2 = Eigen::Vector2d(0.0, 4.0e6);
    m.gap_shapes = Eigen::MatrixXd::Random(6, 2);
    m.residual_flexibility = Eigen::MatrixXd::Random(6, 6);
    m.residual_inertia = Eigen::MatrixXd::Random(6, 6);
    m.groups.push_back({"a", law(), 0, 2});
    m.references.resize(2);
    m.areas = Eigen::Vector2d(1e-6, 1e-6);
    m.stuck_tangents.assign(2, Eigen::Matrix3d::Identity());
    m.outputs.push_back({"o", Eigen::Vector2d(1.0, 2.0), Eigen::VectorXd::Zero(6), Eigen::VectorXd::Zero(6), 0.0, 0.0});
    const std::string good = io::encode_interface_model(m);
    {
      RawRecord r = parse_record(good);
      std::string& columns = r.field("references").bytes;  // u64 count, then the record
      RawRecord references = parse_record(std::string_view(columns).substr(8));
      references.erase("traction");
      columns = columns.substr(0, 8) + emit(references);
      write_cache_file(cache.file("interface_model", "k"), "interface_model", "k", emit(r));
      EXPECT_FALSE(cache.load_interface_model("k", {law()}).has_value());
      expect_miss_naming("ContactPointReference: field 'traction' missing", "interface model references");
    }
    {
      RawRecord r = parse_record(good);
      r.erase("outputs");
      write_cache_file(cache.file("interface_model", "k"), "interface_model", "k", emit(r));
      EXPECT_FALSE(cache.load_interface_model("k", {law()}).has_value());
      expect_miss_naming("InterfaceModel: field 'outputs' missing", "interface model outputs");
    }
    // The good payload through the same writer: a hit.
    const std::size_t warnings = cache.warnings().size();
    write_cache_file(cache.file("interface_model", "k"), "interface_model", "k", good);
    EXPECT_TRUE(cache.load_interface_model("k", {law()}).has_value());
    EXPECT_EQ(cache.warnings().size(), warnings);
  }
}

TEST(StageCacheFormat, VersionOneFileIsAMissWithAWarning) {
  const modal::ModalResult m = hand_made_modes();
  TempDir dir;
  io::StageCache cache(dir.path(), true);
  const fs::path file = cache.file("modes", "k");
  write_cache_file(file, "modes", "k", io::encode_modes(m), 1);
  EXPECT_FALSE(cache.load_modes("k").has_value());
  ASSERT_EQ(cache.warnings().size(), 1u);
  const std::string& warning = cache.warnings().back();
  EXPECT_NE(warning.find("format version 1"), std::string::npos) << warning;
  EXPECT_NE(warning.find(file.string()), std::string::npos) << warning;
  // The same bytes with this build's version: a hit.
  write_cache_file(file, "modes", "k", io::encode_modes(m), io::stage_cache_format);
  EXPECT_TRUE(cache.load_modes("k").has_value());
  EXPECT_EQ(cache.warnings().size(), 1u);
}

TEST(StageCacheFormat, ManyContactPointsCostOnlyTheirData) {
  // references are stored as columns, not a record per point: one more point adds its reference
  // (2 × 3 doubles), its stuck tangent (9 doubles) and its area (1 double), nothing else.
  const auto with_points = [](int points) {
    jointhb::hb::InterfaceModel m;
    m.references.resize(static_cast<std::size_t>(points));
    m.stuck_tangents.assign(static_cast<std::size_t>(points), Eigen::Matrix3d::Identity());
    m.areas = Eigen::VectorXd::Ones(points);
    return io::encode_interface_model(m).size();
  };
  EXPECT_EQ(with_points(101) - with_points(100), (6 + 9 + 1) * sizeof(double));
  EXPECT_EQ(with_points(1000) - with_points(100), 900 * (6 + 9 + 1) * sizeof(double));
}

// ---- the member count behind the compile-time field checks ---------------------------------------

namespace {
struct ThreeScalars {
  double x;
  int i;
  bool flag;
};
struct TwoScalars {  // ThreeScalars without the bool: the same sizeof on x86-64 (padding)
  double x;
  int i;
};
struct WithDefaults {
  int a = 1;
  double b = 2.0;
  std::string s = "s";
};
struct Pair {
  int first;
  int second;
};
struct WithNestedAggregate {  // brace elision would let {any, any, any} fill pair's two ints
  Pair pair;
  int third;
};
struct NotDefaultConstructible {
  explicit NotDefaultConstructible(int) {}
};
struct WithNonDefaultConstructibleMember {  // T{} and T{any} are ill-formed, T{any, any} is not
  int a;
  NotDefaultConstructible b;
};
struct WithLibraryTypes {
  Eigen::VectorXd v;
  Eigen::Matrix3d m3;
  Eigen::SparseMatrix<double> sparse;
  std::vector<bool> flags;
  std::vector<Eigen::Matrix3d> tangents;
  std::string name;
};
struct Empty {};
}  // namespace

TEST(StageCacheFormat, AggregateFieldCountCountsMembersNotBytesOrNestedElements) {
  using jointhb::io::detail::aggregate_field_count;
  EXPECT_EQ(aggregate_field_count<TwoScalars>(), 2u);
  EXPECT_EQ(aggregate_field_count<ThreeScalars>(), 3u);  // a bool hidden in padding still counts
  EXPECT_EQ(aggregate_field_count<WithDefaults>(), 3u);
  EXPECT_EQ(aggregate_field_count<Pair>(), 2u);
  EXPECT_EQ(aggregate_field_count<WithNestedAggregate>(), 2u);
  EXPECT_EQ(aggregate_field_count<WithNonDefaultConstructibleMember>(), 2u);
  EXPECT_EQ(aggregate_field_count<WithLibraryTypes>(), 6u);
  EXPECT_EQ(aggregate_field_count<Empty>(), 0u);
  // The cached types that hold a class without a default constructor (contact::ContactPoint).
  EXPECT_EQ(aggregate_field_count<jointhb::hb::InterfaceGroup>(), 4u);
  static_assert(aggregate_field_count<WithNestedAggregate>() == 2);  // usable in static_assert
}

// ---- the FE case keys ----------------------------------------------------------------------------

TEST(FeCaseFingerprints, ChangeOnlyWithTheirInputs) {
  const std::string base = lap_yaml(kAnalysis);
  const auto k = keys_of(base);
  EXPECT_EQ(k.model.size(), 32u);
  EXPECT_NE(k.model, k.preload);
  EXPECT_NE(k.preload, k.modes);
  const auto same = [&](const std::string& text, const char* what) {
    const auto o = keys_of(text);
    EXPECT_EQ(o.model, k.model) << what;
    EXPECT_EQ(o.preload, k.preload) << what;
    EXPECT_EQ(o.modes, k.modes) << what;
  };
  same(base, "same text");
  // Comments, blank lines and flow/block style do not matter.
  same("# another comment\n\n" + replaced(base, "mu: 0.3,", "mu: 0.3,   # friction\n      "), "comments");
  same(replaced(base, "  preload: {load_steps: 4, tolerance: 1.0e-9}",
                "  preload:\n    load_steps: 4   # four steps\n    tolerance: 1.0e-9"),
       "block style");
  // A single number of the model: every key.
  {
    const auto o = keys_of(replaced(base, "preload: 5000.0}", "preload: 5000.5}"));
    EXPECT_NE(o.model, k.model);
    EXPECT_NE(o.preload, k.preload);
    EXPECT_NE(o.modes, k.modes);
  }
  // The preload settings: preload and modes, not the model.
  {
    const auto o = keys_of(replaced(base, "tolerance: 1.0e-9", "tolerance: 1.0e-10"));
    EXPECT_EQ(o.model, k.model);
    EXPECT_NE(o.preload, k.preload);
    EXPECT_NE(o.modes, k.modes);
  }
  // The mode settings: only modes. (Edits of later analyses — the dynamic stages — enter none of
  // the three keys in the same way: the keys read only model, analysis.preload, analysis.modes.)
  {
    const auto o = keys_of(replaced(base, "count: 10", "count: 12"));
    EXPECT_EQ(o.model, k.model);
    EXPECT_EQ(o.preload, k.preload);
    EXPECT_NE(o.modes, k.modes);
  }
  {
    const auto o = keys_of(replaced(base, "  modes: {count: 10, shift_hz: -10.0}\n", ""));
    EXPECT_EQ(o.model, k.model);
    EXPECT_EQ(o.preload, k.preload);
    EXPECT_NE(o.modes, k.modes);
  }
  // The keys hash the typed values: no analysis.preload gives the defaults, which equal the
  // explicit settings of the base (load_steps 4, tolerance 1e-9), hence the same keys; a value
  // written differently (1.0e-9 vs 0.000000001) is the same value.
  same(replaced(base, "  preload: {load_steps: 4, tolerance: 1.0e-9}\n", ""), "defaults written out");
  same(replaced(base, "tolerance: 1.0e-9", "tolerance: 0.000000001"), "the same number written differently");
}

// A bolt footprint's inner radius (a washer's annulus, eq. B-4) enters the model key even where
// it selects the same faces; an explicit 0 is the disc of a bolt without it.
TEST(FeCaseFingerprints, BoltInnerRadiusEntersTheModelKey) {
  const std::string base = lap_yaml(kAnalysis);
  const auto k = keys_of(base);
  const auto with_inner = [&](const char* inner) {
    return keys_of(replaced(base, "head: {surface: upper.zmax, radius: 0.006}",
                            std::string("head: {surface: upper.zmax, radius: 0.006, inner_radius: ") + inner + "}"));
  };
  EXPECT_EQ(with_inner("0.0").model, k.model);
  // 1 mm: no face centre of the 10 mm mesh lies that close to the axis, the footprint is the same.
  const auto small = with_inner("0.001");
  EXPECT_NE(small.model, k.model);
  EXPECT_NE(small.preload, k.preload);
  EXPECT_NE(small.modes, k.modes);
  EXPECT_NE(with_inner("0.002").model, small.model);
}

TEST(FeCaseFingerprints, ImportedMeshBytesEnterTheModelKey) {
  TempDir dir;
  const std::string brick = R"(*HEADING
brick
*NODE
1, 0., 0., 0.
2, 1., 0., 0.
3, 1., 1., 0.
4, 0., 1., 0.
5, 0., 0., 1.
6, 1., 0., 1.
7, 1., 1., 1.
8, 0., 1., 1.
*ELEMENT, TYPE=C3D8, ELSET=BLOCK
1, 1, 2, 3, 4, 5, 6, 7, 8
)";
  write_bytes(dir.path() / "brick.inp", brick);
  write_bytes(dir.path() / "case.yaml", R"(model:
  type: fe
  materials: {steel: {youngs_modulus: 2.1e11, poissons_ratio: 0.3, density: 7850.0}}
  parts:
    - {mesh: brick.inp, material: steel}
analysis:
  modes: {count: 3}
)");
  const auto keys = [&] {
    const io::FeCase c = io::read_fe_case(dir.path() / "case.yaml");
    return jointhb::pipeline::fe_stage_keys(c, c);
  };
  const auto k = keys();
  EXPECT_EQ(keys().model, k.model);
  write_bytes(dir.path() / "brick.inp", replaced(brick, "8, 0., 1., 1.", "8, 0., 1., 1.01"));
  const auto o = keys();
  EXPECT_NE(o.model, k.model);
  EXPECT_NE(o.preload, k.preload);
  EXPECT_NE(o.modes, k.modes);
}
