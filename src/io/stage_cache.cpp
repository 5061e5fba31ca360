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
#include <type_traits>

#include "jointhb/io/aggregate_field_count.hpp"
#include "jointhb/pipeline/stage_names.hpp"
#include "../support/file_bytes.hpp"

namespace jointhb::io {

namespace stage_names = pipeline::stage_names;

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
// int arrays are copied as a block on little-endian machines where int is the file's i32.
constexpr bool int_is_i32 = std::is_same_v<int, std::int32_t>;

using support::file_bytes;

// ---- the cached types' fields --------------------------------------------------------------------

// Every struct written below is read and written field by field by name, so a member added to one
// of them is lost from the cache unless it is also written and read here. These checks make such
// an addition (or removal) a compile error. They count the members of the aggregate (no sizeof:
// padding would hide a new bool, and sizes differ between platforms). All serialised structs are
// aggregates (public data members, no constructors), which aggregate_field_count also asserts.
// What is not a struct of ours is serialised by its fixed layout (Eigen's dense and sparse
// matrices, std::vector) and has no members to forget. hb::InterfaceGroup::law (a
// contact::ContactPoint: a law object, not data) is counted but deliberately not stored: the
// caller passes the laws to load_interface_model.
using detail::aggregate_field_count;
static_assert(aggregate_field_count<preload::PreloadStep>() == 8,
              "PreloadStep gained or lost a field: serialise it in stage_cache.cpp and bump stage_cache_format");
static_assert(aggregate_field_count<fe::InterfaceContactState>() == 8,
              "InterfaceContactState gained or lost a field: serialise it in stage_cache.cpp and bump "
              "stage_cache_format");
static_assert(aggregate_field_count<preload::InterfaceResult>() == 9,
              "InterfaceResult gained or lost a field: serialise it in stage_cache.cpp and bump stage_cache_format");
static_assert(aggregate_field_count<fe::DofMap>() == 2,
              "DofMap gained or lost a field: serialise it in stage_cache.cpp and bump stage_cache_format");
static_assert(aggregate_field_count<fe::SparseCholeskyStatistics>() == 11,
              "SparseCholeskyStatistics gained or lost a field: serialise it in stage_cache.cpp and bump "
              "stage_cache_format");
static_assert(aggregate_field_count<preload::PreloadResult>() == 18,
              "PreloadResult gained or lost a field: serialise it in stage_cache.cpp and bump stage_cache_format");
static_assert(aggregate_field_count<modal::ModalResult>() == 17,
              "ModalResult gained or lost a field: serialise it in stage_cache.cpp and bump stage_cache_format");
static_assert(aggregate_field_count<hb::InterfaceGroup>() == 4,
              "InterfaceGroup gained or lost a field: serialise it in stage_cache.cpp and bump stage_cache_format");
static_assert(aggregate_field_count<hb::ContactPointReference>() == 2,
              "ContactPointReference gained or lost a field: serialise it in stage_cache.cpp and bump "
              "stage_cache_format");
static_assert(aggregate_field_count<hb::InterfaceOutput>() == 6,
              "InterfaceOutput gained or lost a field: serialise it in stage_cache.cpp and bump stage_cache_format");
static_assert(aggregate_field_count<hb::InterfaceModel>() == 17,
              "InterfaceModel gained or lost a field: serialise it in stage_cache.cpp and bump stage_cache_format");
static_assert(aggregate_field_count<reduction::FieldRecovery>() == 7,
              "FieldRecovery gained or lost a field: serialise it in stage_cache.cpp and bump stage_cache_format");

// ---- bytes -----------------------------------------------------------------------------------------

class ByteWriter {
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
  void bytes(std::string_view s) { out_.append(s.data(), s.size()); }
  void str(std::string_view s) {
    u64(s.size());
    bytes(s);
  }
  void doubles(const double* p, std::size_t n) {
    if constexpr (little_endian) {
      out_.append(reinterpret_cast<const char*>(p), n * sizeof(double));
    } else {
      for (std::size_t i = 0; i < n; ++i) f64(p[i]);
    }
  }
  void ints(const int* p, std::size_t n) {
    if constexpr (little_endian && int_is_i32) {
      out_.append(reinterpret_cast<const char*>(p), n * sizeof(int));
    } else {
      for (std::size_t i = 0; i < n; ++i) i32(p[i]);
    }
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

  /// Where the next byte goes, and overwriting a u32 or u64 written earlier there: the counts and
  /// lengths of records are written before their contents and filled in after them, so that a
  /// nested record needs no buffer of its own (no extra copy of a large matrix).
  [[nodiscard]] std::size_t position() const { return out_.size(); }
  void patch_u32(std::size_t at, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) out_[at + k] = static_cast<char>((v >> (8 * k)) & 0xffU);
  }
  void patch_u64(std::size_t at, std::uint64_t v) {
    for (int k = 0; k < 8; ++k) out_[at + k] = static_cast<char>((v >> (8 * k)) & 0xffU);
  }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

class ByteReader {
 public:
  explicit ByteReader(std::string_view in) : in_(in) {}

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
  /// A u64 length and that many bytes, as a view into the input.
  std::string_view str() { return take(count(1)); }
  /// A count of items of `item_size` bytes each that must fit in what is left.
  std::size_t count(std::size_t item_size) {
    const std::uint64_t n = u64();
    if (item_size > 0 && n > left() / item_size) throw std::runtime_error("truncated or bad size");
    return static_cast<std::size_t>(n);
  }
  void doubles(double* p, std::size_t n) {
    if (n > left() / sizeof(double)) throw std::runtime_error("truncated");
    const std::string_view b = take(n * sizeof(double));
    if constexpr (little_endian) {
      if (n > 0) std::memcpy(p, b.data(), b.size());
    } else {
      ByteReader r(b);
      for (std::size_t i = 0; i < n; ++i) p[i] = r.f64();
    }
  }
  void ints(int* p, std::size_t n) {
    if (n > left() / 4) throw std::runtime_error("truncated");
    if constexpr (little_endian && int_is_i32) {
      const std::string_view b = take(n * sizeof(int));
      if (n > 0) std::memcpy(p, b.data(), b.size());
    } else {
      for (std::size_t i = 0; i < n; ++i) p[i] = i32();
    }
  }
  Eigen::SparseMatrix<double> sparse() {
    const std::uint64_t rows = u64(), cols = u64(), nnz = u64();
    const std::uint64_t limit = static_cast<std::uint64_t>(std::numeric_limits<int>::max());
    if (rows > limit || cols > limit || nnz > left() / 12) throw std::runtime_error("bad sparse matrix size");
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
  [[nodiscard]] std::size_t left() const { return in_.size() - pos_; }
  std::string_view take(std::size_t n) {
    if (n > left()) throw std::runtime_error("truncated");
    const std::string_view b = in_.substr(pos_, n);
    pos_ += n;
    return b;
  }

 private:
  std::string_view in_;
  std::size_t pos_ = 0;
};

// ---- records -------------------------------------------------------------------------------------

/// The one-byte type code of a field (stage_cache.hpp lists them): what the bytes hold, so that a
/// field whose C++ type changed is a clear mismatch instead of a misread. Never renumber a code.
enum class FieldType : std::uint8_t {
  boolean = 1,
  int32 = 2,
  int64 = 3,
  float64 = 4,
  string = 5,
  enumeration = 6,
  float64_array = 7,
  float64_matrix = 8,
  int32_array = 9,
  boolean_array = 10,
  matrix3_array = 11,
  vector3_array = 12,
  sparse_matrix = 13,
  record = 14,
  record_list = 15,
  record_columns = 16,
};

std::string type_name(std::uint8_t code) {
  switch (static_cast<FieldType>(code)) {
    case FieldType::boolean: return "boolean";
    case FieldType::int32: return "int32";
    case FieldType::int64: return "int64";
    case FieldType::float64: return "float64";
    case FieldType::string: return "string";
    case FieldType::enumeration: return "enumeration";
    case FieldType::float64_array: return "float64 array";
    case FieldType::float64_matrix: return "float64 matrix";
    case FieldType::int32_array: return "int32 array";
    case FieldType::boolean_array: return "boolean array";
    case FieldType::matrix3_array: return "3x3 matrix array";
    case FieldType::vector3_array: return "3-vector array";
    case FieldType::sparse_matrix: return "sparse matrix";
    case FieldType::record: return "record";
    case FieldType::record_list: return "record list";
    case FieldType::record_columns: return "record columns";
  }
  return "unknown";
}

/// Writes one record: its type name, a u32 field count and the fields (name, type code, u64
/// length, bytes). The count and each length are filled in when the record or field is complete.
class RecordWriter {
 public:
  RecordWriter(ByteWriter& w, std::string_view type) : w_(w) {
    w_.str(type);
    count_at_ = w_.position();
    w_.u32(0);
  }
  RecordWriter(const RecordWriter&) = delete;
  RecordWriter& operator=(const RecordWriter&) = delete;
  ~RecordWriter() { w_.patch_u32(count_at_, fields_); }

  void boolean(std::string_view name, bool v) {
    field(name, FieldType::boolean, [&] { w_.boolean(v); });
  }
  void int32(std::string_view name, int v) {
    field(name, FieldType::int32, [&] { w_.i32(v); });
  }
  void int64(std::string_view name, long v) {
    field(name, FieldType::int64, [&] { w_.i64(v); });
  }
  void float64(std::string_view name, double v) {
    field(name, FieldType::float64, [&] { w_.f64(v); });
  }
  void string(std::string_view name, std::string_view v) {
    field(name, FieldType::string, [&] { w_.bytes(v); });
  }
  void enumeration(std::string_view name, std::uint8_t v) {
    field(name, FieldType::enumeration, [&] { w_.u8(v); });
  }
  void reals(std::string_view name, const Eigen::VectorXd& v) {
    field(name, FieldType::float64_array, [&] { w_.doubles(v.data(), static_cast<std::size_t>(v.size())); });
  }
  void reals(std::string_view name, const std::vector<double>& v) {
    field(name, FieldType::float64_array, [&] { w_.doubles(v.data(), v.size()); });
  }
  void matrix(std::string_view name, const Eigen::MatrixXd& m) {
    field(name, FieldType::float64_matrix, [&] {
      w_.u64(static_cast<std::uint64_t>(m.rows()));
      w_.u64(static_cast<std::uint64_t>(m.cols()));
      w_.doubles(m.data(), static_cast<std::size_t>(m.size()));
    });
  }
  void integers(std::string_view name, const std::vector<int>& v) {
    field(name, FieldType::int32_array, [&] { w_.ints(v.data(), v.size()); });
  }
  void flags(std::string_view name, const std::vector<bool>& v) {
    field(name, FieldType::boolean_array, [&] {
      for (const bool b : v) w_.boolean(b);
    });
  }
  void matrices3(std::string_view name, const std::vector<Eigen::Matrix3d>& ms) {
    field(name, FieldType::matrix3_array, [&] {
      for (const auto& m : ms) w_.doubles(m.data(), 9);
    });
  }
  /// The `member` 3-vector of each item, one after another.
  template <class Item>
  void vectors3(std::string_view name, const std::vector<Item>& items, Eigen::Vector3d Item::*member) {
    field(name, FieldType::vector3_array, [&] {
      for (const auto& item : items) w_.doubles((item.*member).data(), 3);
    });
  }
  void sparse(std::string_view name, const Eigen::SparseMatrix<double>& a) {
    field(name, FieldType::sparse_matrix, [&] { w_.sparse(a); });
  }
  /// A nested record: put(RecordWriter&) writes its fields.
  template <class Put>
  void record(std::string_view name, std::string_view type, Put put) {
    field(name, FieldType::record, [&] {
      RecordWriter r(w_, type);
      put(r);
    });
  }
  /// A u64 count and one record per item: put(RecordWriter&, const Item&).
  template <class Item, class Put>
  void records(std::string_view name, std::string_view type, const std::vector<Item>& items, Put put) {
    field(name, FieldType::record_list, [&] {
      w_.u64(items.size());
      for (const auto& item : items) {
        RecordWriter r(w_, type);
        put(r, item);
      }
    });
  }
  /// Many small items without a record each: a u64 count and one record whose fields hold the
  /// items' values of that field one after another (put(RecordWriter&) writes them).
  template <class Put>
  void columns(std::string_view name, std::string_view type, std::size_t count, Put put) {
    field(name, FieldType::record_columns, [&] {
      w_.u64(count);
      RecordWriter r(w_, type);
      put(r);
    });
  }

 private:
  template <class Body>
  void field(std::string_view name, FieldType type, Body body) {
    w_.str(name);
    w_.u8(static_cast<std::uint8_t>(type));
    const std::size_t length_at = w_.position();
    w_.u64(0);
    body();
    w_.patch_u64(length_at, w_.position() - length_at - 8);
    ++fields_;
  }

  ByteWriter& w_;
  std::size_t count_at_ = 0;
  std::uint32_t fields_ = 0;
};

/// Reads one record: checks its type name, indexes its fields by name, and hands out each field's
/// value by name and type code. A field this build expects but the record lacks, a field of
/// another type code or length, and (at finish) a field this build does not know throw
/// std::runtime_error naming the record type and the field.
class RecordReader {
  // (first: the public members below use their deduced return types)
  struct Field {
    std::string_view name;
    std::uint8_t type = 0;
    std::string_view bytes;
    bool read = false;
  };

  Field& field(std::string_view name, FieldType type) {
    for (Field& f : fields_) {
      if (f.name != name) continue;
      if (f.type != static_cast<std::uint8_t>(type))
        throw std::runtime_error(fmt::format("{}: field '{}' has type code {} ({}), expected {} ({})", type_, name,
                                             static_cast<int>(f.type), type_name(f.type), static_cast<int>(type),
                                             type_name(static_cast<std::uint8_t>(type))));
      f.read = true;
      return f;
    }
    throw std::runtime_error(fmt::format("{}: field '{}' missing", type_, name));
  }
  /// The field's value get(ByteReader&), which must use all its bytes; a failure names the field.
  template <class Get>
  auto value(std::string_view name, FieldType type, Get get) {
    ByteReader r(field(name, type).bytes);
    try {
      auto v = get(r);
      r.expect_end();
      return v;
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(fmt::format("{}: field '{}': {}", type_, name, e.what()));
    }
  }
  template <class Get>
  auto fixed(std::string_view name, FieldType type, std::size_t length, Get get) {
    const std::size_t found = field(name, type).bytes.size();
    if (found != length)
      throw std::runtime_error(fmt::format("{}: field '{}' has {} bytes, expected {}", type_, name, found, length));
    return value(name, type, get);
  }
  /// The number of items of item_size bytes that make up the rest of r (inside value(), which
  /// names the field).
  static std::size_t items(const ByteReader& r, std::size_t item_size) {
    if (r.left() % item_size != 0)
      throw std::runtime_error(fmt::format("{} bytes, not a multiple of {}", r.left(), item_size));
    return r.left() / item_size;
  }

 public:
  RecordReader(ByteReader& r, std::string_view type) : type_(type) {
    const std::string_view found = r.str();
    if (found != type) throw std::runtime_error(fmt::format("expected a {} record, found '{}'", type, found));
    const std::uint32_t n = r.u32();
    if (n > r.left() / 17) throw std::runtime_error(fmt::format("{}: truncated (field count {})", type, n));
    fields_.reserve(n);
    for (std::uint32_t k = 0; k < n; ++k) {
      Field f;
      f.name = r.str();
      f.type = r.u8();
      const std::uint64_t length = r.u64();
      if (length > r.left()) throw std::runtime_error(fmt::format("{}: field '{}' is truncated", type_, f.name));
      f.bytes = r.take(static_cast<std::size_t>(length));
      for (const Field& g : fields_)
        if (g.name == f.name) throw std::runtime_error(fmt::format("{}: field '{}' appears twice", type_, f.name));
      fields_.push_back(f);
    }
  }

  bool boolean(std::string_view name) {
    return fixed(name, FieldType::boolean, 1, [](ByteReader& r) { return r.boolean(); });
  }
  int int32(std::string_view name) {
    return fixed(name, FieldType::int32, 4, [](ByteReader& r) { return r.i32(); });
  }
  long int64(std::string_view name) {
    return fixed(name, FieldType::int64, 8, [](ByteReader& r) { return r.i64(); });
  }
  double float64(std::string_view name) {
    return fixed(name, FieldType::float64, 8, [](ByteReader& r) { return r.f64(); });
  }
  std::uint8_t enumeration(std::string_view name) {
    return fixed(name, FieldType::enumeration, 1, [](ByteReader& r) { return r.u8(); });
  }
  std::string string(std::string_view name) { return std::string(field(name, FieldType::string).bytes); }
  Eigen::VectorXd vector(std::string_view name) {
    return value(name, FieldType::float64_array, [&](ByteReader& r) {
      Eigen::VectorXd v(static_cast<Eigen::Index>(items(r, sizeof(double))));
      r.doubles(v.data(), static_cast<std::size_t>(v.size()));
      return v;
    });
  }
  std::vector<double> reals(std::string_view name) {
    return value(name, FieldType::float64_array, [&](ByteReader& r) {
      std::vector<double> v(items(r, sizeof(double)));
      r.doubles(v.data(), v.size());
      return v;
    });
  }
  Eigen::MatrixXd matrix(std::string_view name) {
    return value(name, FieldType::float64_matrix, [&](ByteReader& r) {
      const std::uint64_t rows = r.u64(), cols = r.u64();
      const std::uint64_t left = r.left() / sizeof(double);
      const auto limit = static_cast<std::uint64_t>(std::numeric_limits<Eigen::Index>::max());
      if (rows > left || cols > limit || (rows > 0 && cols > left / rows) || rows * cols * sizeof(double) != r.left())
        throw std::runtime_error(fmt::format("{} × {} does not match its {} bytes", rows, cols, r.left()));
      Eigen::MatrixXd m(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
      r.doubles(m.data(), static_cast<std::size_t>(m.size()));
      return m;
    });
  }
  std::vector<int> integers(std::string_view name) {
    return value(name, FieldType::int32_array, [&](ByteReader& r) {
      std::vector<int> v(items(r, 4));
      r.ints(v.data(), v.size());
      return v;
    });
  }
  std::vector<bool> flags(std::string_view name) {
    return value(name, FieldType::boolean_array, [&](ByteReader& r) {
      std::vector<bool> v(r.left());
      for (std::size_t i = 0; i < v.size(); ++i) v[i] = r.boolean();
      return v;
    });
  }
  std::vector<Eigen::Matrix3d> matrices3(std::string_view name) {
    return value(name, FieldType::matrix3_array, [&](ByteReader& r) {
      std::vector<Eigen::Matrix3d> ms(items(r, 9 * sizeof(double)));
      for (auto& m : ms) r.doubles(m.data(), 9);
      return ms;
    });
  }
  /// Sets the `member` 3-vector of each of `items` (their count must match the field's).
  template <class Item>
  void vectors3(std::string_view name, std::vector<Item>& items_out, Eigen::Vector3d Item::*member) {
    value(name, FieldType::vector3_array, [&](ByteReader& r) {
      const std::size_t n = items(r, 3 * sizeof(double));
      if (n != items_out.size())
        throw std::runtime_error(fmt::format("{} items, the record has {}", n, items_out.size()));
      for (auto& item : items_out) r.doubles((item.*member).data(), 3);
      return 0;
    });
  }
  Eigen::SparseMatrix<double> sparse(std::string_view name) {
    return value(name, FieldType::sparse_matrix, [](ByteReader& r) { return r.sparse(); });
  }
  /// A nested record: get(RecordReader&) returns its value.
  template <class Get>
  auto record(std::string_view name, std::string_view type, Get get) {
    return value(name, FieldType::record, [&](ByteReader& r) { return read_record(r, type, get); });
  }
  /// A list of records: get(RecordReader&) returns each item.
  template <class Get>
  auto records(std::string_view name, std::string_view type, Get get) {
    return value(name, FieldType::record_list, [&](ByteReader& r) {
      std::vector<decltype(read_record(r, type, get))> items_out(r.count(8 + type.size() + 4));
      for (auto& item : items_out) item = read_record(r, type, get);
      return items_out;
    });
  }
  /// Items written by RecordWriter::columns: get(RecordReader&, std::size_t count) returns them.
  /// item_bytes (the bytes of one item in all columns) bounds the count before get allocates.
  template <class Get>
  auto columns(std::string_view name, std::string_view type, std::size_t item_bytes, Get get) {
    return value(name, FieldType::record_columns, [&](ByteReader& r) {
      const std::size_t count = r.count(item_bytes);
      return read_record(r, type, [&](RecordReader& rec) { return get(rec, count); });
    });
  }

  /// Throws when the record has a field that was not read: one this build does not know.
  void finish() const {
    for (const Field& f : fields_)
      if (!f.read)
        throw std::runtime_error(fmt::format("{}: unknown field '{}' (type {})", type_, f.name, type_name(f.type)));
  }

  /// A record from r, its value get(RecordReader&), all its fields read.
  template <class Get>
  static auto read_record(ByteReader& r, std::string_view type, Get get) {
    RecordReader rec(r, type);
    auto v = get(rec);
    rec.finish();
    return v;
  }

 private:
  std::string_view type_;
  std::vector<Field> fields_;
};

/// The payload: one top-level record and nothing after it.
template <class Get>
auto decode_payload(std::string_view payload, std::string_view type, Get get) {
  ByteReader r(payload);
  auto v = RecordReader::read_record(r, type, get);
  r.expect_end();
  return v;
}

template <class Put>
std::string encode_payload(std::string_view type, Put put) {
  ByteWriter w;
  {
    RecordWriter r(w, type);
    put(r);
  }
  return w.take();
}

void put(RecordWriter& w, const fe::SparseCholeskyStatistics& s) {
  w.int64("rows", s.rows);
  w.int64("matrix_nonzeros", s.matrix_nonzeros);
  w.float64("factor_nonzeros", s.factor_nonzeros);
  w.int64("factor_entries", s.factor_entries);
  w.float64("factor_flops", s.factor_flops);
  w.string("ordering", s.ordering);
  w.int32("factorizations", s.factorizations);
  w.float64("analyze_seconds", s.analyze_seconds);
  w.float64("factorize_seconds", s.factorize_seconds);
  w.int64("iterations", s.iterations);
  w.int64("solved_columns", s.solved_columns);
}

// A Termination (contact/termination.hpp) as an enumeration field: its enumerator's value.
void put_termination(RecordWriter& w, Termination t) {
  w.enumeration("termination", static_cast<std::uint8_t>(t));
}

Termination get_termination(RecordReader& r, std::string_view type) {
  const std::uint8_t t = r.enumeration("termination");
  if (t > static_cast<std::uint8_t>(Termination::failed))
    throw std::runtime_error(fmt::format("{}: field 'termination' has no enumerator {}", type, t));
  return static_cast<Termination>(t);
}

fe::SparseCholeskyStatistics get_factor(RecordReader& r) {
  fe::SparseCholeskyStatistics s;
  s.rows = r.int64("rows");
  s.matrix_nonzeros = r.int64("matrix_nonzeros");
  s.factor_nonzeros = r.float64("factor_nonzeros");
  s.factor_entries = r.int64("factor_entries");
  s.factor_flops = r.float64("factor_flops");
  s.ordering = r.string("ordering");
  s.factorizations = r.int32("factorizations");
  s.analyze_seconds = r.float64("analyze_seconds");
  s.factorize_seconds = r.float64("factorize_seconds");
  s.iterations = r.int64("iterations");
  s.solved_columns = r.int64("solved_columns");
  return s;
}

}  // namespace

// ---- payloads ------------------------------------------------------------------------------------

std::string encode_preload(const preload::PreloadResult& p) {
  return encode_payload("PreloadResult", [&](RecordWriter& w) {
    put_termination(w, p.termination);
    w.string("message", p.message);
    w.records("steps", "PreloadStep", p.steps, [](RecordWriter& ws, const preload::PreloadStep& s) {
      ws.float64("load_factor", s.load_factor);
      ws.int32("iterations", s.iterations);
      ws.int32("factorizations", s.factorizations);
      ws.int32("chord_iterations", s.chord_iterations);
      ws.int32("line_search_cuts", s.line_search_cuts);
      ws.float64("residual", s.residual);
      put_termination(ws, s.termination);
      ws.string("message", s.message);
    });
    w.reals("displacement", p.displacement);
    w.float64("load_factor", p.load_factor);
    w.records("interfaces", "InterfaceResult", p.interfaces, [](RecordWriter& wi, const preload::InterfaceResult& i) {
      wi.string("name", i.name);
      wi.record("state", "InterfaceContactState", [&](RecordWriter& wc) {
        wc.reals("gap", i.state.gap);
        wc.reals("traction", i.state.traction);
        wc.reals("pressure", i.state.pressure);
        wc.matrices3("tangent", i.state.tangent);
        wc.flags("open", i.state.open);
        wc.int32("num_open", i.state.num_open);
        wc.reals("force", i.state.force);
        wc.sparse("stiffness", i.state.stiffness);
      });
      wi.float64("clamping_force", i.clamping_force);
      wi.float64("closed_area", i.closed_area);
      wi.float64("closed_area_fraction", i.closed_area_fraction);
      wi.float64("max_pressure", i.max_pressure);
      wi.float64("mean_pressure", i.mean_pressure);
      wi.float64("max_gap", i.max_gap);
      wi.float64("min_gap", i.min_gap);
    });
    w.reals("bolt_forces", p.bolt_forces);
    w.integers("support_dofs", p.support_dofs);
    w.float64("support_reaction", p.support_reaction);
    w.record("dofs", "DofMap", [&](RecordWriter& wd) {
      wd.integers("free_of_full", p.dofs.free_of_full);
      wd.integers("full_of_free", p.dofs.full_of_free);
    });
    w.sparse("dynamic_stiffness", p.dynamic_stiffness);
    w.string("factor_statistics", p.factor_statistics);
    w.record("factor", "SparseCholeskyStatistics", [&](RecordWriter& wf) { put(wf, p.factor); });
    w.int32("total_iterations", p.total_iterations);
    w.float64("assembly_seconds", p.assembly_seconds);
    w.float64("contact_seconds", p.contact_seconds);
    w.float64("factor_seconds", p.factor_seconds);
    w.float64("seconds", p.seconds);
  });
}

preload::PreloadResult decode_preload(std::string_view payload) {
  return decode_payload(payload, "PreloadResult", [](RecordReader& r) {
    preload::PreloadResult p;
    p.termination = get_termination(r, "PreloadResult");
    p.message = r.string("message");
    p.steps = r.records("steps", "PreloadStep", [](RecordReader& rs) {
      preload::PreloadStep s;
      s.load_factor = rs.float64("load_factor");
      s.iterations = rs.int32("iterations");
      s.factorizations = rs.int32("factorizations");
      s.chord_iterations = rs.int32("chord_iterations");
      s.line_search_cuts = rs.int32("line_search_cuts");
      s.residual = rs.float64("residual");
      s.termination = get_termination(rs, "PreloadStep");
      s.message = rs.string("message");
      return s;
    });
    p.displacement = r.vector("displacement");
    p.load_factor = r.float64("load_factor");
    p.interfaces = r.records("interfaces", "InterfaceResult", [](RecordReader& ri) {
      preload::InterfaceResult i;
      i.name = ri.string("name");
      i.state = ri.record("state", "InterfaceContactState", [](RecordReader& rc) {
        fe::InterfaceContactState c;
        c.gap = rc.vector("gap");
        c.traction = rc.vector("traction");
        c.pressure = rc.vector("pressure");
        c.tangent = rc.matrices3("tangent");
        c.open = rc.flags("open");
        c.num_open = rc.int32("num_open");
        c.force = rc.vector("force");
        c.stiffness = rc.sparse("stiffness");
        return c;
      });
      i.clamping_force = ri.float64("clamping_force");
      i.closed_area = ri.float64("closed_area");
      i.closed_area_fraction = ri.float64("closed_area_fraction");
      i.max_pressure = ri.float64("max_pressure");
      i.mean_pressure = ri.float64("mean_pressure");
      i.max_gap = ri.float64("max_gap");
      i.min_gap = ri.float64("min_gap");
      return i;
    });
    p.bolt_forces = r.reals("bolt_forces");
    p.support_dofs = r.integers("support_dofs");
    p.support_reaction = r.float64("support_reaction");
    p.dofs = r.record("dofs", "DofMap", [](RecordReader& rd) {
      fe::DofMap d;
      d.free_of_full = rd.integers("free_of_full");
      d.full_of_free = rd.integers("full_of_free");
      return d;
    });
    p.dynamic_stiffness = r.sparse("dynamic_stiffness");
    p.factor_statistics = r.string("factor_statistics");
    p.factor = r.record("factor", "SparseCholeskyStatistics", get_factor);
    p.total_iterations = r.int32("total_iterations");
    p.assembly_seconds = r.float64("assembly_seconds");
    p.contact_seconds = r.float64("contact_seconds");
    p.factor_seconds = r.float64("factor_seconds");
    p.seconds = r.float64("seconds");
    return p;
  });
}

std::string encode_modes(const modal::ModalResult& m) {
  return encode_payload("ModalResult", [&](RecordWriter& w) {
    put_termination(w, m.termination);
    w.string("message", m.message);
    w.reals("eigenvalues", m.eigenvalues);
    w.reals("frequencies_hz", m.frequencies_hz);
    w.matrix("shapes", m.shapes);
    w.reals("residuals", m.residuals);
    w.reals("backward_errors", m.backward_errors);
    w.float64("shift", m.shift);
    w.int32("requested", m.requested);
    w.int32("iterations", m.iterations);
    w.int32("operator_applications", m.operator_applications);
    w.int32("mass_applications", m.mass_applications);
    w.int32("ncv", m.ncv);
    w.record("factor", "SparseCholeskyStatistics", [&](RecordWriter& wf) { put(wf, m.factor); });
    w.float64("factor_seconds", m.factor_seconds);
    w.float64("lanczos_seconds", m.lanczos_seconds);
    w.float64("seconds", m.seconds);
  });
}

modal::ModalResult decode_modes(std::string_view payload) {
  return decode_payload(payload, "ModalResult", [](RecordReader& r) {
    modal::ModalResult m;
    m.termination = get_termination(r, "ModalResult");
    m.message = r.string("message");
    m.eigenvalues = r.vector("eigenvalues");
    m.frequencies_hz = r.vector("frequencies_hz");
    m.shapes = r.matrix("shapes");
    m.residuals = r.vector("residuals");
    m.backward_errors = r.vector("backward_errors");
    m.shift = r.float64("shift");
    m.requested = r.int32("requested");
    m.iterations = r.int32("iterations");
    m.operator_applications = r.int32("operator_applications");
    m.mass_applications = r.int32("mass_applications");
    m.ncv = r.int32("ncv");
    m.factor = r.record("factor", "SparseCholeskyStatistics", get_factor);
    m.factor_seconds = r.float64("factor_seconds");
    m.lanczos_seconds = r.float64("lanczos_seconds");
    m.seconds = r.float64("seconds");
    return m;
  });
}

std::string encode_interface_model(const hb::InterfaceModel& m) {
  return encode_payload("InterfaceModel", [&](RecordWriter& w) {
    w.reals("omega2", m.omega2);
    w.int32("rigid_modes", m.rigid_modes);
    w.matrix("gap_shapes", m.gap_shapes);
    w.float64("rayleigh_mass", m.rayleigh_mass);
    w.float64("rayleigh_stiffness", m.rayleigh_stiffness);
    w.float64("residual_shift", m.residual_shift);
    w.matrix("residual_flexibility", m.residual_flexibility);
    w.matrix("residual_inertia", m.residual_inertia);
    w.records("groups", "InterfaceGroup", m.groups, [](RecordWriter& wg, const hb::InterfaceGroup& g) {
      wg.string("name", g.name);  // the law is the caller's (see load_interface_model)
      wg.int32("first", g.first);
      wg.int32("count", g.count);
    });
    // One record per contact point would cost more than the point's 48 bytes of data: columns.
    w.columns("references", "ContactPointReference", m.references.size(), [&](RecordWriter& wr) {
      wr.vectors3("gap", m.references, &hb::ContactPointReference::gap);
      wr.vectors3("traction", m.references, &hb::ContactPointReference::traction);
    });
    w.reals("areas", m.areas);
    w.matrices3("stuck_tangents", m.stuck_tangents);
    w.string("load_name", m.load_name);
    w.reals("load_modal", m.load_modal);
    w.reals("load_residual0", m.load_residual0);
    w.reals("load_residual1", m.load_residual1);
    w.records("outputs", "InterfaceOutput", m.outputs, [](RecordWriter& wo, const hb::InterfaceOutput& o) {
      wo.string("name", o.name);
      wo.reals("modal", o.modal);
      wo.reals("residual0", o.residual0);
      wo.reals("residual1", o.residual1);
      wo.float64("load_residual0", o.load_residual0);
      wo.float64("load_residual1", o.load_residual1);
    });
  });
}

hb::InterfaceModel decode_interface_model(std::string_view payload,
                                          const std::vector<contact::ContactPoint>& laws) {
  return decode_payload(payload, "InterfaceModel", [&](RecordReader& r) {
    hb::InterfaceModel m;
    m.omega2 = r.vector("omega2");
    m.rigid_modes = r.int32("rigid_modes");
    m.gap_shapes = r.matrix("gap_shapes");
    m.rayleigh_mass = r.float64("rayleigh_mass");
    m.rayleigh_stiffness = r.float64("rayleigh_stiffness");
    m.residual_shift = r.float64("residual_shift");
    m.residual_flexibility = r.matrix("residual_flexibility");
    m.residual_inertia = r.matrix("residual_inertia");
    struct StoredGroup {
      std::string name;
      int first = 0, count = 0;
    };
    const std::vector<StoredGroup> groups = r.records("groups", "InterfaceGroup", [](RecordReader& rg) {
      StoredGroup g;
      g.name = rg.string("name");
      g.first = rg.int32("first");
      g.count = rg.int32("count");
      return g;
    });
    if (groups.size() != laws.size())
      throw std::invalid_argument(fmt::format("{} interface groups stored, {} contact laws given", groups.size(), laws.size()));
    for (std::size_t g = 0; g < groups.size(); ++g)
      m.groups.push_back(hb::InterfaceGroup{groups[g].name, laws[g], groups[g].first, groups[g].count});
    m.references = r.columns("references", "ContactPointReference", 6 * sizeof(double),
                             [](RecordReader& rr, std::size_t count) {
      std::vector<hb::ContactPointReference> references(count);
      rr.vectors3("gap", references, &hb::ContactPointReference::gap);
      rr.vectors3("traction", references, &hb::ContactPointReference::traction);
      return references;
    });
    m.areas = r.vector("areas");
    m.stuck_tangents = r.matrices3("stuck_tangents");
    m.load_name = r.string("load_name");
    m.load_modal = r.vector("load_modal");
    m.load_residual0 = r.vector("load_residual0");
    m.load_residual1 = r.vector("load_residual1");
    m.outputs = r.records("outputs", "InterfaceOutput", [](RecordReader& ro) {
      hb::InterfaceOutput o;
      o.name = ro.string("name");
      o.modal = ro.vector("modal");
      o.residual0 = ro.vector("residual0");
      o.residual1 = ro.vector("residual1");
      o.load_residual0 = ro.float64("load_residual0");
      o.load_residual1 = ro.float64("load_residual1");
      return o;
    });
    return m;
  });
}

std::string encode_field_recovery(const reduction::FieldRecovery& f) {
  return encode_payload("FieldRecovery", [&](RecordWriter& w) {
    w.matrix("modes", f.modes);
    w.matrix("residual", f.residual);
    w.integers("column_of_row", f.column_of_row);
    w.reals("load_residual", f.load_residual);
    w.integers("full_of_free", f.full_of_free);
    w.int32("num_full", f.num_full);
    w.float64("rayleigh_stiffness", f.rayleigh_stiffness);
  });
}

reduction::FieldRecovery decode_field_recovery(std::string_view payload) {
  reduction::FieldRecovery f = decode_payload(payload, "FieldRecovery", [](RecordReader& r) {
    reduction::FieldRecovery g;
    g.modes = r.matrix("modes");
    g.residual = r.matrix("residual");
    g.column_of_row = r.integers("column_of_row");
    g.load_residual = r.vector("load_residual");
    g.full_of_free = r.integers("full_of_free");
    g.num_full = r.int32("num_full");
    g.rayleigh_stiffness = r.float64("rayleigh_stiffness");
    return g;
  });
  const auto n = static_cast<Eigen::Index>(f.full_of_free.size());
  if (f.modes.rows() != n || f.residual.rows() != n || f.load_residual.size() != n)
    throw std::runtime_error("inconsistent field-recovery sizes");
  for (int c : f.column_of_row)
    if (c < 0 || c >= f.residual.cols()) throw std::runtime_error("field-recovery column out of range");
  for (int d : f.full_of_free)
    if (d < 0 || d >= f.num_full) throw std::runtime_error("field-recovery DOF out of range");
  return f;
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
    ByteReader r(bytes);
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
    ByteReader tail(std::string_view(bytes).substr(header + static_cast<std::size_t>(length)));
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
    ByteWriter w;
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

std::optional<reduction::FieldRecovery> StageCache::load_field_recovery(const std::string& key) {
  const auto payload = read_payload(stage_names::recovery, key);
  if (!payload) return std::nullopt;
  try {
    return decode_field_recovery(*payload);
  } catch (const std::exception& e) {
    warn(fmt::format("stage cache: {} does not parse ({}); recomputing the condensation", file(stage_names::recovery, key).string(),
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
  write_payload(stage_names::recovery, key, payload);
}

std::optional<preload::PreloadResult> StageCache::load_preload(const std::string& key) {
  const auto payload = read_payload(stage_names::preload, key);
  if (!payload) return std::nullopt;
  try {
    return decode_preload(*payload);
  } catch (const std::exception& e) {
    warn(fmt::format("stage cache: {} does not parse ({}); recomputing preload", file(stage_names::preload, key).string(), e.what()));
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
  write_payload(stage_names::preload, key, payload);
}

std::optional<modal::ModalResult> StageCache::load_modes(const std::string& key) {
  const auto payload = read_payload(stage_names::modes, key);
  if (!payload) return std::nullopt;
  try {
    return decode_modes(*payload);
  } catch (const std::exception& e) {
    warn(fmt::format("stage cache: {} does not parse ({}); recomputing modes", file(stage_names::modes, key).string(), e.what()));
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
  write_payload(stage_names::modes, key, payload);
}

std::optional<hb::InterfaceModel> StageCache::load_interface_model(
    const std::string& key, const std::vector<contact::ContactPoint>& laws) {
  const auto payload = read_payload(stage_names::interface_model, key);
  if (!payload) return std::nullopt;
  try {
    return decode_interface_model(*payload, laws);
  } catch (const std::exception& e) {
    warn(fmt::format("stage cache: {} does not fit ({}); recomputing interface_model",
                     file(stage_names::interface_model, key).string(), e.what()));
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
  write_payload(stage_names::interface_model, key, payload);
}

}  // namespace jointhb::io
