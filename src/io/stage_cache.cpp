#include "jointhb/io/stage_cache.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <bit>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <system_error>

namespace jointhb::io {
namespace {

std::uint64_t fnv1a64(std::string_view bytes) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

constexpr bool little_endian = std::endian::native == std::endian::little;

/// The whole file; nullopt when it cannot be opened or read.
std::optional<std::string> file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  if (!in) return std::nullopt;
  const std::streamoff size = in.tellg();
  if (size < 0) return std::nullopt;
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0);
  if (!in.read(bytes.data(), size)) return std::nullopt;
  return bytes;
}

// ---- payload encoding ------------------------------------------------------------------------

class Writer {
 public:
  void u8(std::uint8_t v) { out_.push_back(static_cast<char>(v)); }
  void u32(std::uint32_t v) {
    for (int k = 0; k < 4; ++k) out_.push_back(static_cast<char>((v >> (8 * k)) & 0xffU));
  }
  void u64(std::uint64_t v) {
    for (int k = 0; k < 8; ++k) out_.push_back(static_cast<char>((v >> (8 * k)) & 0xffU));
  }
  void i32(int v) { u32(static_cast<std::uint32_t>(v)); }
  void i64(long v) { u64(static_cast<std::uint64_t>(v)); }
  void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
  void boolean(bool v) { u8(v ? 1 : 0); }
  void str(std::string_view s) {
    u64(s.size());
    out_.append(s.data(), s.size());
  }
  void doubles(const double* p, std::size_t n) {
    if constexpr (little_endian) {
      out_.append(reinterpret_cast<const char*>(p), n * sizeof(double));
    } else {
      for (std::size_t i = 0; i < n; ++i) f64(p[i]);
    }
  }
  void ints(const int* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) i32(p[i]);
  }
  void vec(const Eigen::VectorXd& v) {
    u64(static_cast<std::uint64_t>(v.size()));
    doubles(v.data(), static_cast<std::size_t>(v.size()));
  }
  void mat(const Eigen::MatrixXd& m) {
    u64(static_cast<std::uint64_t>(m.rows()));
    u64(static_cast<std::uint64_t>(m.cols()));
    doubles(m.data(), static_cast<std::size_t>(m.size()));
  }
  void mat3(const Eigen::Matrix3d& m) { doubles(m.data(), 9); }
  void vec3(const Eigen::Vector3d& v) { doubles(v.data(), 3); }
  void mat3s(const std::vector<Eigen::Matrix3d>& ms) {
    u64(ms.size());
    for (const auto& m : ms) mat3(m);
  }
  void reals(const std::vector<double>& v) {
    u64(v.size());
    doubles(v.data(), v.size());
  }
  void integers(const std::vector<int>& v) {
    u64(v.size());
    ints(v.data(), v.size());
  }
  void flags(const std::vector<bool>& v) {
    u64(v.size());
    for (const bool b : v) boolean(b);
  }
  void sparse(const Eigen::SparseMatrix<double>& a) {
    Eigen::SparseMatrix<double> c = a;  // compressed copy: outer, inner, values
    c.makeCompressed();
    u64(static_cast<std::uint64_t>(c.rows()));
    u64(static_cast<std::uint64_t>(c.cols()));
    u64(static_cast<std::uint64_t>(c.nonZeros()));
    ints(c.outerIndexPtr(), static_cast<std::size_t>(c.outerSize()) + 1);
    ints(c.innerIndexPtr(), static_cast<std::size_t>(c.nonZeros()));
    doubles(c.valuePtr(), static_cast<std::size_t>(c.nonZeros()));
  }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

class Reader {
 public:
  explicit Reader(std::string_view in) : in_(in) {}

  std::uint8_t u8() { return static_cast<std::uint8_t>(take(1)[0]); }
  std::uint32_t u32() {
    const std::string_view b = take(4);
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v |= static_cast<std::uint32_t>(static_cast<unsigned char>(b[k])) << (8 * k);
    return v;
  }
  std::uint64_t u64() {
    const std::string_view b = take(8);
    std::uint64_t v = 0;
    for (int k = 0; k < 8; ++k) v |= static_cast<std::uint64_t>(static_cast<unsigned char>(b[k])) << (8 * k);
    return v;
  }
  int i32() { return static_cast<int>(u32()); }
  long i64() { return static_cast<long>(u64()); }
  double f64() { return std::bit_cast<double>(u64()); }
  bool boolean() {
    const std::uint8_t v = u8();
    if (v > 1) throw std::runtime_error("bad boolean");
    return v == 1;
  }
  std::string str() {
    const std::string_view b = take(count(1));
    return std::string(b);
  }
  /// A count of items of `item_size` bytes each that must fit in what is left.
  std::size_t count(std::size_t item_size) {
    const std::uint64_t n = u64();
    if (item_size > 0 && n > (in_.size() - pos_) / item_size) throw std::runtime_error("truncated or bad size");
    return static_cast<std::size_t>(n);
  }
  void doubles(double* p, std::size_t n) {
    const std::string_view b = take(n * sizeof(double));
    if constexpr (little_endian) {
      if (n > 0) std::memcpy(p, b.data(), b.size());
    } else {
      Reader r(b);
      for (std::size_t i = 0; i < n; ++i) p[i] = r.f64();
    }
  }
  void ints(int* p, std::size_t n) {
    if (n > (in_.size() - pos_) / 4) throw std::runtime_error("truncated");
    for (std::size_t i = 0; i < n; ++i) p[i] = i32();
  }
  Eigen::VectorXd vec() {
    Eigen::VectorXd v(static_cast<Eigen::Index>(count(sizeof(double))));
    doubles(v.data(), static_cast<std::size_t>(v.size()));
    return v;
  }
  Eigen::MatrixXd mat() {
    const std::uint64_t rows = u64(), cols = u64();
    const std::uint64_t left = (in_.size() - pos_) / sizeof(double);
    if (rows > left || (rows > 0 && cols > left / rows)) throw std::runtime_error("truncated or bad size");
    Eigen::MatrixXd m(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
    doubles(m.data(), static_cast<std::size_t>(m.size()));
    return m;
  }
  Eigen::Matrix3d mat3() {
    Eigen::Matrix3d m;
    doubles(m.data(), 9);
    return m;
  }
  Eigen::Vector3d vec3() {
    Eigen::Vector3d v;
    doubles(v.data(), 3);
    return v;
  }
  std::vector<Eigen::Matrix3d> mat3s() {
    std::vector<Eigen::Matrix3d> ms(count(9 * sizeof(double)));
    for (auto& m : ms) m = mat3();
    return ms;
  }
  std::vector<double> reals() {
    std::vector<double> v(count(sizeof(double)));
    doubles(v.data(), v.size());
    return v;
  }
  std::vector<int> integers() {
    std::vector<int> v(count(4));
    ints(v.data(), v.size());
    return v;
  }
  std::vector<bool> flags() {
    std::vector<bool> v(count(1));
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = boolean();
    return v;
  }
  Eigen::SparseMatrix<double> sparse() {
    const std::uint64_t rows = u64(), cols = u64(), nnz = u64();
    const std::uint64_t limit = static_cast<std::uint64_t>(std::numeric_limits<int>::max());
    if (rows > limit || cols > limit || nnz > (in_.size() - pos_) / 12) throw std::runtime_error("bad sparse matrix size");
    Eigen::SparseMatrix<double> a(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
    std::vector<int> outer(static_cast<std::size_t>(cols) + 1), inner(static_cast<std::size_t>(nnz));
    ints(outer.data(), outer.size());
    ints(inner.data(), inner.size());
    if (outer.front() != 0 || static_cast<std::uint64_t>(outer.back()) != nnz) throw std::runtime_error("bad sparse matrix");
    for (std::size_t j = 0; j + 1 < outer.size(); ++j)
      if (outer[j + 1] < outer[j]) throw std::runtime_error("bad sparse matrix");
    for (const int i : inner)
      if (i < 0 || static_cast<std::uint64_t>(i) >= rows) throw std::runtime_error("bad sparse matrix");
    a.resizeNonZeros(static_cast<Eigen::Index>(nnz));
    std::copy(outer.begin(), outer.end(), a.outerIndexPtr());
    std::copy(inner.begin(), inner.end(), a.innerIndexPtr());
    doubles(a.valuePtr(), static_cast<std::size_t>(nnz));
    return a;
  }
  void expect_end() const {
    if (pos_ != in_.size()) throw std::runtime_error(fmt::format("{} trailing bytes", in_.size() - pos_));
  }
  [[nodiscard]] std::size_t position() const { return pos_; }

 private:
  std::string_view take(std::size_t n) {
    if (n > in_.size() - pos_) throw std::runtime_error("truncated");
    const std::string_view b = in_.substr(pos_, n);
    pos_ += n;
    return b;
  }
  std::string_view in_;
  std::size_t pos_ = 0;
};

void put(Writer& w, const fe::SparseCholeskyStatistics& s) {
  w.i64(s.rows);
  w.i64(s.matrix_nonzeros);
  w.f64(s.factor_nonzeros);
  w.i64(s.factor_entries);
  w.f64(s.factor_flops);
  w.str(s.ordering);
  w.i32(s.factorizations);
  w.f64(s.analyze_seconds);
  w.f64(s.factorize_seconds);
}

fe::SparseCholeskyStatistics get_factor(Reader& r) {
  fe::SparseCholeskyStatistics s;
  s.rows = r.i64();
  s.matrix_nonzeros = r.i64();
  s.factor_nonzeros = r.f64();
  s.factor_entries = r.i64();
  s.factor_flops = r.f64();
  s.ordering = r.str();
  s.factorizations = r.i32();
  s.analyze_seconds = r.f64();
  s.factorize_seconds = r.f64();
  return s;
}

// A field added to one of the cached types must be serialised too (and stage_cache_format
// bumped). The sizes below catch an addition on the usual platform (x86-64, libstdc++).
#if defined(__x86_64__) && defined(__GLIBCXX__) && !defined(_GLIBCXX_DEBUG)
static_assert(sizeof(preload::PreloadStep) == 40, "PreloadStep changed: update stage_cache.cpp");
static_assert(sizeof(preload::InterfaceResult) == 296, "InterfaceResult changed: update stage_cache.cpp");
static_assert(sizeof(fe::InterfaceContactState) == 208, "InterfaceContactState changed: update stage_cache.cpp");
static_assert(sizeof(preload::PreloadResult) == 456, "PreloadResult changed: update stage_cache.cpp");
static_assert(sizeof(fe::SparseCholeskyStatistics) == 96, "SparseCholeskyStatistics changed: update stage_cache.cpp");
static_assert(sizeof(modal::ModalResult) == 280, "ModalResult changed: update stage_cache.cpp");
static_assert(sizeof(hb::InterfaceModel) == 312, "InterfaceModel changed: update stage_cache.cpp");
static_assert(sizeof(hb::InterfaceGroup) == 120, "InterfaceGroup changed: update stage_cache.cpp");
static_assert(sizeof(hb::InterfaceOutput) == 96, "InterfaceOutput changed: update stage_cache.cpp");
#endif

}  // namespace

// ---- payloads ------------------------------------------------------------------------------------

std::string encode_preload(const preload::PreloadResult& p) {
  Writer w;
  w.boolean(p.converged);
  w.str(p.message);
  w.u64(p.steps.size());
  for (const auto& s : p.steps) {
    w.f64(s.load_factor);
    w.i32(s.iterations);
    w.i32(s.factorizations);
    w.i32(s.chord_iterations);
    w.i32(s.line_search_cuts);
    w.f64(s.residual);
    w.boolean(s.converged);
  }
  w.vec(p.displacement);
  w.f64(p.load_factor);
  w.u64(p.interfaces.size());
  for (const auto& i : p.interfaces) {
    w.str(i.name);
    w.vec(i.state.gap);
    w.vec(i.state.traction);
    w.vec(i.state.pressure);
    w.mat3s(i.state.tangent);
    w.flags(i.state.open);
    w.i32(i.state.num_open);
    w.vec(i.state.force);
    w.sparse(i.state.stiffness);
    w.f64(i.clamping_force);
    w.f64(i.closed_area);
    w.f64(i.closed_area_fraction);
    w.f64(i.max_pressure);
    w.f64(i.mean_pressure);
    w.f64(i.max_gap);
    w.f64(i.min_gap);
  }
  w.reals(p.bolt_forces);
  w.integers(p.support_dofs);
  w.f64(p.support_reaction);
  w.integers(p.dofs.free_of_full);
  w.integers(p.dofs.full_of_free);
  w.sparse(p.dynamic_stiffness);
  w.str(p.factor_statistics);
  put(w, p.factor);
  w.i32(p.total_iterations);
  w.f64(p.assembly_seconds);
  w.f64(p.contact_seconds);
  w.f64(p.factor_seconds);
  w.f64(p.seconds);
  return w.take();
}

preload::PreloadResult decode_preload(std::string_view payload) {
  Reader r(payload);
  preload::PreloadResult p;
  p.converged = r.boolean();
  p.message = r.str();
  p.steps.resize(r.count(33));
  for (auto& s : p.steps) {
    s.load_factor = r.f64();
    s.iterations = r.i32();
    s.factorizations = r.i32();
    s.chord_iterations = r.i32();
    s.line_search_cuts = r.i32();
    s.residual = r.f64();
    s.converged = r.boolean();
  }
  p.displacement = r.vec();
  p.load_factor = r.f64();
  p.interfaces.resize(r.count(1));
  for (auto& i : p.interfaces) {
    i.name = r.str();
    i.state.gap = r.vec();
    i.state.traction = r.vec();
    i.state.pressure = r.vec();
    i.state.tangent = r.mat3s();
    i.state.open = r.flags();
    i.state.num_open = r.i32();
    i.state.force = r.vec();
    i.state.stiffness = r.sparse();
    i.clamping_force = r.f64();
    i.closed_area = r.f64();
    i.closed_area_fraction = r.f64();
    i.max_pressure = r.f64();
    i.mean_pressure = r.f64();
    i.max_gap = r.f64();
    i.min_gap = r.f64();
  }
  p.bolt_forces = r.reals();
  p.support_dofs = r.integers();
  p.support_reaction = r.f64();
  p.dofs.free_of_full = r.integers();
  p.dofs.full_of_free = r.integers();
  p.dynamic_stiffness = r.sparse();
  p.factor_statistics = r.str();
  p.factor = get_factor(r);
  p.total_iterations = r.i32();
  p.assembly_seconds = r.f64();
  p.contact_seconds = r.f64();
  p.factor_seconds = r.f64();
  p.seconds = r.f64();
  r.expect_end();
  return p;
}

std::string encode_modes(const modal::ModalResult& m) {
  Writer w;
  w.u8(static_cast<std::uint8_t>(m.status));
  w.str(m.message);
  w.vec(m.eigenvalues);
  w.vec(m.frequencies_hz);
  w.mat(m.shapes);
  w.vec(m.residuals);
  w.vec(m.backward_errors);
  w.f64(m.shift);
  w.i32(m.requested);
  w.i32(m.iterations);
  w.i32(m.operator_applications);
  w.i32(m.mass_applications);
  w.i32(m.ncv);
  put(w, m.factor);
  w.f64(m.factor_seconds);
  w.f64(m.lanczos_seconds);
  w.f64(m.seconds);
  return w.take();
}

modal::ModalResult decode_modes(std::string_view payload) {
  Reader r(payload);
  modal::ModalResult m;
  const std::uint8_t status = r.u8();
  if (status > static_cast<std::uint8_t>(modal::ModalStatus::failed)) throw std::runtime_error("bad modal status");
  m.status = static_cast<modal::ModalStatus>(status);
  m.message = r.str();
  m.eigenvalues = r.vec();
  m.frequencies_hz = r.vec();
  m.shapes = r.mat();
  m.residuals = r.vec();
  m.backward_errors = r.vec();
  m.shift = r.f64();
  m.requested = r.i32();
  m.iterations = r.i32();
  m.operator_applications = r.i32();
  m.mass_applications = r.i32();
  m.ncv = r.i32();
  m.factor = get_factor(r);
  m.factor_seconds = r.f64();
  m.lanczos_seconds = r.f64();
  m.seconds = r.f64();
  r.expect_end();
  return m;
}

std::string encode_interface_model(const hb::InterfaceModel& m) {
  Writer w;
  w.vec(m.omega2);
  w.i32(m.rigid_modes);
  w.mat(m.gap_shapes);
  w.f64(m.rayleigh_mass);
  w.f64(m.rayleigh_stiffness);
  w.f64(m.residual_shift);
  w.mat(m.residual_flexibility);
  w.mat(m.residual_inertia);
  w.u64(m.groups.size());
  for (const auto& g : m.groups) {
    w.str(g.name);  // the law is the caller's (see load_interface_model)
    w.i32(g.first);
    w.i32(g.count);
  }
  w.u64(m.references.size());
  for (const auto& ref : m.references) {
    w.vec3(ref.gap);
    w.vec3(ref.traction);
  }
  w.vec(m.areas);
  w.mat3s(m.stuck_tangents);
  w.str(m.load_name);
  w.vec(m.load_modal);
  w.vec(m.load_residual0);
  w.vec(m.load_residual1);
  w.u64(m.outputs.size());
  for (const auto& o : m.outputs) {
    w.str(o.name);
    w.vec(o.modal);
    w.vec(o.residual0);
    w.vec(o.residual1);
    w.f64(o.load_residual0);
    w.f64(o.load_residual1);
  }
  return w.take();
}

hb::InterfaceModel decode_interface_model(std::string_view payload,
                                          const std::vector<contact::ContactPoint>& laws) {
  Reader r(payload);
  hb::InterfaceModel m;
  m.omega2 = r.vec();
  m.rigid_modes = r.i32();
  m.gap_shapes = r.mat();
  m.rayleigh_mass = r.f64();
  m.rayleigh_stiffness = r.f64();
  m.residual_shift = r.f64();
  m.residual_flexibility = r.mat();
  m.residual_inertia = r.mat();
  const std::size_t groups = r.count(16);
  if (groups != laws.size())
    throw std::invalid_argument(fmt::format("{} interface groups stored, {} contact laws given", groups, laws.size()));
  for (std::size_t g = 0; g < groups; ++g) {
    std::string name = r.str();
    const int first = r.i32();
    const int count = r.i32();
    m.groups.push_back(hb::InterfaceGroup{std::move(name), laws[g], first, count});
  }
  m.references.resize(r.count(6 * sizeof(double)));
  for (auto& ref : m.references) {
    ref.gap = r.vec3();
    ref.traction = r.vec3();
  }
  m.areas = r.vec();
  m.stuck_tangents = r.mat3s();
  m.load_name = r.str();
  m.load_modal = r.vec();
  m.load_residual0 = r.vec();
  m.load_residual1 = r.vec();
  m.outputs.resize(r.count(1));
  for (auto& o : m.outputs) {
    o.name = r.str();
    o.modal = r.vec();
    o.residual0 = r.vec();
    o.residual1 = r.vec();
    o.load_residual0 = r.f64();
    o.load_residual1 = r.f64();
  }
  r.expect_end();
  return m;
}

// ---- StageCache ----------------------------------------------------------------------------------

StageCache::StageCache(std::filesystem::path dir, bool enabled) : dir_(std::move(dir)), enabled_(enabled) {}

std::filesystem::path StageCache::file(std::string_view stage, std::string_view key) const {
  return dir_ / fmt::format("{}-{}.bin", stage, key);
}

void StageCache::warn(const std::string& message) {
  std::string line = message;
  for (char& c : line)
    if (c == '\n' || c == '\r') c = ' ';
  std::fprintf(stderr, "warning: %s\n", line.c_str());
  warnings_.push_back(line);
}

std::optional<std::string> StageCache::read_payload(std::string_view stage, const std::string& key) {
  if (!enabled_) return std::nullopt;
  const std::filesystem::path path = file(stage, key);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
  const std::optional<std::string> read = file_bytes(path);
  if (!read) {
    warn(fmt::format("stage cache: cannot read {}; recomputing {}", path.string(), stage));
    return std::nullopt;
  }
  const std::string& bytes = *read;
  const auto bad = [&](const std::string& why) -> std::optional<std::string> {
    warn(fmt::format("stage cache: {} {}; recomputing {}", path.string(), why, stage));
    return std::nullopt;
  };
  try {
    Reader r(bytes);
    if (bytes.size() < 4 || bytes.compare(0, 4, "JHBC") != 0) return bad("is not a jointhb cache file (bad magic)");
    r.u32();  // the magic
    const std::uint32_t version = r.u32();
    if (version != stage_cache_format)
      return bad(fmt::format("has cache format version {}, this program reads version {}", version, stage_cache_format));
    if (r.str() != stage) return bad("holds another stage");
    if (r.str() != key) return bad("holds another key");
    const std::uint64_t length = r.u64();
    const std::size_t header = r.position();
    if (length > bytes.size() || bytes.size() - header != length + 8)
      return bad(fmt::format("is truncated or has trailing bytes ({} bytes, {} expected)", bytes.size(), header + length + 8));
    std::string payload = bytes.substr(header, static_cast<std::size_t>(length));
    Reader tail(std::string_view(bytes).substr(header + static_cast<std::size_t>(length)));
    if (tail.u64() != fnv1a64(payload)) return bad("is corrupted (checksum mismatch)");
    return payload;
  } catch (const std::exception& e) {
    return bad(fmt::format("is truncated or corrupted ({})", e.what()));
  }
}

void StageCache::write_payload(std::string_view stage, const std::string& key, const std::string& payload) {
  if (!enabled_) return;
  const std::filesystem::path path = file(stage, key);
  std::filesystem::path temp;
  try {
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec) {
      warn(fmt::format("stage cache: cannot create {}: {}; {} not cached", dir_.string(), ec.message(), stage));
      return;
    }
    Writer w;
    w.u8('J'), w.u8('H'), w.u8('B'), w.u8('C');
    w.u32(stage_cache_format);
    w.str(stage);
    w.str(key);
    w.u64(payload.size());
    const std::string header = w.take();
    w.u64(fnv1a64(payload));
    const std::string checksum = w.take();
    temp = dir_ / fmt::format(".{}-{}.bin.tmp{}", stage, key, static_cast<long>(::getpid()));
    {
      std::ofstream out(temp, std::ios::binary | std::ios::trunc);
      out.write(header.data(), static_cast<std::streamsize>(header.size()));
      out.write(payload.data(), static_cast<std::streamsize>(payload.size()));
      out.write(checksum.data(), static_cast<std::streamsize>(checksum.size()));
      out.close();
      if (!out) {
        std::filesystem::remove(temp, ec);
        warn(fmt::format("stage cache: cannot write {} (disk full or no permission?); {} not cached", temp.string(), stage));
        return;
      }
    }
    std::filesystem::rename(temp, path, ec);
    if (ec) {
      std::filesystem::remove(temp, ec);
      warn(fmt::format("stage cache: cannot rename to {}: {}; {} not cached", path.string(), ec.message(), stage));
    }
  } catch (const std::exception& e) {
    std::error_code ignored;
    if (!temp.empty()) std::filesystem::remove(temp, ignored);
    warn(fmt::format("stage cache: cannot store {}: {}; not cached", path.string(), e.what()));
  }
}

std::string encode_field_recovery(const reduction::FieldRecovery& f) {
  Writer w;
  w.mat(f.modes);
  w.mat(f.residual);
  w.integers(f.column_of_row);
  w.vec(f.load_residual);
  w.integers(f.full_of_free);
  w.i32(f.num_full);
  w.f64(f.rayleigh_stiffness);
  return w.take();
}

reduction::FieldRecovery decode_field_recovery(std::string_view payload) {
  Reader r(payload);
  reduction::FieldRecovery f;
  f.modes = r.mat();
  f.residual = r.mat();
  f.column_of_row = r.integers();
  f.load_residual = r.vec();
  f.full_of_free = r.integers();
  f.num_full = r.i32();
  f.rayleigh_stiffness = r.f64();
  r.expect_end();
  const auto n = static_cast<Eigen::Index>(f.full_of_free.size());
  if (f.modes.rows() != n || f.residual.rows() != n || f.load_residual.size() != n)
    throw std::runtime_error("inconsistent field-recovery sizes");
  for (int c : f.column_of_row)
    if (c < 0 || c >= f.residual.cols()) throw std::runtime_error("field-recovery column out of range");
  for (int d : f.full_of_free)
    if (d < 0 || d >= f.num_full) throw std::runtime_error("field-recovery DOF out of range");
  return f;
}

std::optional<reduction::FieldRecovery> StageCache::load_field_recovery(const std::string& key) {
  const auto payload = read_payload("recovery", key);
  if (!payload) return std::nullopt;
  try {
    return decode_field_recovery(*payload);
  } catch (const std::exception& e) {
    warn(fmt::format("stage cache: {} does not parse ({}); recomputing the condensation", file("recovery", key).string(),
                     e.what()));
    return std::nullopt;
  }
}

void StageCache::store_field_recovery(const std::string& key, const reduction::FieldRecovery& recovery) {
  if (!enabled_) return;
  std::string payload;
  try {
    payload = encode_field_recovery(recovery);
  } catch (const std::exception& e) {
    warn(fmt::format("stage cache: cannot encode the field recovery: {}; not cached", e.what()));
    return;
  }
  write_payload("recovery", key, payload);
}

std::optional<preload::PreloadResult> StageCache::load_preload(const std::string& key) {
  const auto payload = read_payload("preload", key);
  if (!payload) return std::nullopt;
  try {
    return decode_preload(*payload);
  } catch (const std::exception& e) {
    warn(fmt::format("stage cache: {} does not parse ({}); recomputing preload", file("preload", key).string(), e.what()));
    return std::nullopt;
  }
}

void StageCache::store_preload(const std::string& key, const preload::PreloadResult& result) {
  if (!enabled_) return;
  std::string payload;
  try {
    payload = encode_preload(result);
  } catch (const std::exception& e) {
    warn(fmt::format("stage cache: cannot encode preload: {}; not cached", e.what()));
    return;
  }
  write_payload("preload", key, payload);
}

std::optional<modal::ModalResult> StageCache::load_modes(const std::string& key) {
  const auto payload = read_payload("modes", key);
  if (!payload) return std::nullopt;
  try {
    return decode_modes(*payload);
  } catch (const std::exception& e) {
    warn(fmt::format("stage cache: {} does not parse ({}); recomputing modes", file("modes", key).string(), e.what()));
    return std::nullopt;
  }
}

void StageCache::store_modes(const std::string& key, const modal::ModalResult& result) {
  if (!enabled_) return;
  std::string payload;
  try {
    payload = encode_modes(result);
  } catch (const std::exception& e) {
    warn(fmt::format("stage cache: cannot encode modes: {}; not cached", e.what()));
    return;
  }
  write_payload("modes", key, payload);
}

std::optional<hb::InterfaceModel> StageCache::load_interface_model(
    const std::string& key, const std::vector<contact::ContactPoint>& laws) {
  const auto payload = read_payload("interface_model", key);
  if (!payload) return std::nullopt;
  try {
    return decode_interface_model(*payload, laws);
  } catch (const std::exception& e) {
    warn(fmt::format("stage cache: {} does not fit ({}); recomputing interface_model",
                     file("interface_model", key).string(), e.what()));
    return std::nullopt;
  }
}

void StageCache::store_interface_model(const std::string& key, const hb::InterfaceModel& model) {
  if (!enabled_) return;
  std::string payload;
  try {
    payload = encode_interface_model(model);
  } catch (const std::exception& e) {
    warn(fmt::format("stage cache: cannot encode interface_model: {}; not cached", e.what()));
    return;
  }
  write_payload("interface_model", key, payload);
}

}  // namespace jointhb::io
