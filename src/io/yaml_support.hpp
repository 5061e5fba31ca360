#pragma once
// What the case-file readers share (private to the io layer): loading a file and its YAML, and a
// reader that reports every problem at the node it concerns, as
//   FILE:LINE:COLUMN: key 'a.b[1].c': CONSTRAINT
// (include/jointhb/io/input_error.hpp). yaml-cpp stays out of the public headers.

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace jointhb::io::yaml {

/// The whole file as text. Throws InputError (no position) for a directory or an unreadable file.
std::string read_text_file(const std::filesystem::path& file);

/// The YAML document in `text`. Throws InputError at the position of a syntax error (no key).
YAML::Node load(const std::string& text, const std::string& file_name);

/// `path` + ".name" (or `name` at the top level).
std::string child_path(const std::string& path, const std::string& name);
/// `path` + "[index]".
std::string item_path(const std::string& path, std::size_t index);

/// The entries of one mapping, checked for unknown and duplicate keys, kept in file order.
class Fields {
 public:
  struct Entry {
    std::string name;
    YAML::Node key;    ///< the key node (positions of "duplicate", "not both", ...)
    YAML::Node value;  ///< the value node
  };

  [[nodiscard]] bool has(const std::string& name) const { return find(name) != nullptr; }
  /// The entry called `name`, or nullptr.
  [[nodiscard]] const Entry* find(const std::string& name) const;
  [[nodiscard]] const std::vector<Entry>& entries() const { return entries_; }
  [[nodiscard]] const std::string& path() const { return path_; }
  /// The full key path of entry `name`.
  [[nodiscard]] std::string path_of(const std::string& name) const {
    return child_path(path_, name);
  }

 private:
  friend class Reader;
  std::string path_;
  std::vector<Entry> entries_;
};

/// Reads one document, reporting every problem at the node it concerns.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[nodiscard]] const std::string& file() const { return file_; }

  [[noreturn]] void fail(const YAML::Node& at, const std::string& key,
                         const std::string& constraint) const;
  [[noreturn]] void fail(const YAML::Mark& mark, const std::string& key,
                         const std::string& constraint) const;

  /// The entries of the mapping `map` at `path`, rejecting a non-mapping, duplicate keys and keys
  /// not in `allowed`. `unknown`, when given, phrases the error for an unknown key (default:
  /// "unknown key; allowed: ...").
  [[nodiscard]] Fields fields(
      const YAML::Node& map, const std::string& path, const std::set<std::string>& allowed,
      const std::function<std::string(const std::string& key)>& unknown = {}) const;

  /// Calls `read(key_path, value)` for each entry of a mapping in file order, rejecting duplicate
  /// and unknown keys.
  void for_each_entry(const YAML::Node& map, const std::string& path,
                      const std::set<std::string>& allowed,
                      const std::function<void(const std::string&, const YAML::Node&)>& read) const;

  /// A number as written (may be non-finite: callers check the range, which names nan and inf).
  [[nodiscard]] double number(const YAML::Node& node, const std::string& path) const;
  /// A finite number.
  [[nodiscard]] double finite_number(const YAML::Node& node, const std::string& path) const;
  [[nodiscard]] long long integer(const YAML::Node& node, const std::string& path) const;
  [[nodiscard]] std::string text(const YAML::Node& node, const std::string& path) const;
  /// `true` or `false`.
  [[nodiscard]] bool boolean(const YAML::Node& node, const std::string& path) const;
  /// The true/false entry `name` of `f` into `value`, when given (left unchanged otherwise).
  void flag(const Fields& f, const std::string& name, bool& value) const;

  /// Fails at `node` with `error` unless it is empty (the value_checks convention).
  void check(const YAML::Node& node, const std::string& path, const std::string& error) const;

  /// "nothing", "a sequence", "a mapping", "'41.5'" or "string '0.3'" (quoted in the file).
  [[nodiscard]] static std::string describe(const YAML::Node& node);
  /// "a, b, c".
  [[nodiscard]] static std::string list(const std::set<std::string>& names);
  /// A scalar written without quotes (a quoted "0.3" is a string in YAML).
  [[nodiscard]] static bool is_plain_scalar(const YAML::Node& node);

 private:
  std::string file_;
};

}  // namespace jointhb::io::yaml
