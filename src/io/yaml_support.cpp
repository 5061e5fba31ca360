#include "yaml_support.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "jointhb/io/input_error.hpp"
#include "jointhb/io/value_checks.hpp"

namespace jointhb::io::yaml {

std::string read_text_file(const std::filesystem::path& file) {
  std::error_code ignored;
  if (std::filesystem::is_directory(file, ignored)) {
    throw InputError(file.string(), 0, 0, "", "cannot open case file: it is a directory");
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    throw InputError(file.string(), 0, 0, "",
                     std::string("cannot open case file: ") + std::strerror(errno));
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) {
    throw InputError(file.string(), 0, 0, "", "cannot read case file");
  }
  return text.str();
}

namespace {

// yaml-cpp 0.7 never returns from LoadAll when a line outside any flow collection starts with ','
// (found by tests/corpus/fuzz_readers.py: "# comment\n, a" or "[1]\n,"). Such a line is refused
// first, with its position. Only a continuation line of a multi-line plain scalar could start with
// ',' legitimately, which no case file needs. The scan follows [ ] { } outside quotes (a quote
// opens a scalar only after ':', '-', ',', '[', '{' or at a line start: "Gaul's" is plain text)
// and comments.
void refuse_line_starting_with_comma(const std::string& text, const std::string& file_name) {
  int depth = 0, line = 1, column = 0;
  bool line_start = true;
  char quote = 0;
  char previous = '\n';  // the last character that was not a blank
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    ++column;
    if (c == '\n') {
      ++line;
      column = 0;
      line_start = true;
      if (quote == '#') quote = 0;
      continue;
    }
    if (quote == '#') continue;  // inside a comment
    if (quote) {
      if (c == quote) quote = 0;
      continue;
    }
    if (line_start && (c == ' ' || c == '\t' || c == '\r')) continue;
    if (line_start && c == ',' && depth == 0) {
      throw InputError(file_name, line, column, "",
                       "invalid YAML: a line starts with ',' outside a flow collection [ ] or { }");
    }
    const bool scalar_start = line_start || std::strchr(":-,[{", previous) != nullptr;
    line_start = false;
    if (c == ' ' || c == '\t') continue;
    if (c == '#' && (i == 0 || text[i - 1] == ' ' || text[i - 1] == '\t')) quote = '#';
    else if ((c == '"' || c == '\'') && scalar_start) quote = c;
    else if (c == '[' || c == '{') ++depth;
    else if ((c == ']' || c == '}') && depth > 0) --depth;
    previous = c;
  }
}

}  // namespace

YAML::Node load(const std::string& text, const std::string& file_name) {
  refuse_line_starting_with_comma(text, file_name);
  std::vector<YAML::Node> documents;
  try {
    documents = YAML::LoadAll(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(file_name, e.mark.line + 1, e.mark.column + 1, "", "invalid YAML: " + e.msg);
  }
  // Only the first document is a case: anything after a '---' separator would be silently
  // ignored, so it is refused (an empty trailing document holds nothing and is harmless).
  for (std::size_t k = 1; k < documents.size(); ++k) {
    if (documents[k].IsNull()) continue;
    const YAML::Mark mark = documents[k].Mark();
    throw InputError(file_name, mark.line + 1, mark.column + 1, "",
                     "a second YAML document (after '---'): a case file holds one document, the "
                     "rest would be ignored");
  }
  return documents.empty() ? YAML::Node() : documents.front();
}

std::string child_path(const std::string& path, const std::string& name) {
  return path.empty() ? name : path + '.' + name;
}

std::string item_path(const std::string& path, std::size_t index) {
  return path + '[' + std::to_string(index) + ']';
}

const Fields::Entry* Fields::find(const std::string& name) const {
  for (const Entry& entry : entries_) {
    if (entry.name == name) return &entry;
  }
  return nullptr;
}

void Reader::fail(const YAML::Node& at, const std::string& key,
                  const std::string& constraint) const {
  fail(at.Mark(), key, constraint);
}

void Reader::fail(const YAML::Mark& mark, const std::string& key,
                  const std::string& constraint) const {
  // yaml-cpp marks are 0-based and -1 when there is no position (an empty document).
  throw InputError(file_, mark.line + 1, mark.column + 1, key, constraint);
}

Fields Reader::fields(const YAML::Node& map, const std::string& path,
                      const std::set<std::string>& allowed,
                      const std::function<std::string(const std::string&)>& unknown) const {
  if (!map.IsMap()) fail(map, path, "must be a mapping, got " + describe(map));
  Fields fields;
  fields.path_ = path;
  for (auto it = map.begin(); it != map.end(); ++it) {
    // Copies: the iterator's operator-> returns a proxy that dies at the end of the statement.
    const YAML::Node key_node = it->first;
    const YAML::Node value = it->second;
    if (!key_node.IsScalar()) fail(key_node, path, "keys must be plain names");
    const std::string& key = key_node.Scalar();
    const std::string key_path = child_path(path, key);
    if (!allowed.count(key)) {
      fail(key_node, key_path, unknown ? unknown(key) : "unknown key; allowed: " + list(allowed));
    }
    if (fields.has(key)) fail(key_node, key_path, "duplicate key");
    fields.entries_.push_back({key, key_node, value});
  }
  return fields;
}

void Reader::for_each_entry(
    const YAML::Node& map, const std::string& path, const std::set<std::string>& allowed,
    const std::function<void(const std::string&, const YAML::Node&)>& read) const {
  // Reads each value as soon as its key is accepted, so that problems are reported in file order.
  if (!map.IsMap()) fail(map, path, "must be a mapping, got " + describe(map));
  std::set<std::string> seen;
  for (auto it = map.begin(); it != map.end(); ++it) {
    const YAML::Node key_node = it->first;
    const YAML::Node value = it->second;
    if (!key_node.IsScalar()) fail(key_node, path, "keys must be plain names");
    const std::string& key = key_node.Scalar();
    const std::string key_path = child_path(path, key);
    if (!allowed.count(key)) fail(key_node, key_path, "unknown key; allowed: " + list(allowed));
    if (!seen.insert(key).second) fail(key_node, key_path, "duplicate key");
    read(key_path, value);
  }
}

double Reader::number(const YAML::Node& node, const std::string& path) const {
  if (!is_plain_scalar(node)) fail(node, path, "must be a number, got " + describe(node));
  const auto value = parse_number(node.Scalar());
  if (!value) fail(node, path, "must be a number, got " + describe(node));
  return *value;
}

double Reader::finite_number(const YAML::Node& node, const std::string& path) const {
  const double value = number(node, path);
  check(node, path, check_finite(value));
  return value;
}

long long Reader::integer(const YAML::Node& node, const std::string& path) const {
  if (!is_plain_scalar(node)) fail(node, path, "must be an integer, got " + describe(node));
  const auto value = parse_integer(node.Scalar());
  if (!value) fail(node, path, "must be an integer, got " + describe(node));
  return *value;
}

std::string Reader::text(const YAML::Node& node, const std::string& path) const {
  if (!node.IsScalar()) fail(node, path, "must be a string, got " + describe(node));
  return node.Scalar();
}

bool Reader::boolean(const YAML::Node& node, const std::string& path) const {
  const std::string value = text(node, path);
  check(node, path, check_one_of(value, {"true", "false"}));
  return value == "true";
}

void Reader::flag(const Fields& f, const std::string& name, bool& value) const {
  if (const Fields::Entry* e = f.find(name)) value = boolean(e->value, f.path_of(name));
}

void Reader::check(const YAML::Node& node, const std::string& path,
                   const std::string& error) const {
  if (!error.empty()) fail(node, path, error);
}

bool Reader::is_plain_scalar(const YAML::Node& node) {
  return node.IsScalar() && node.Tag() != "!";
}

std::string Reader::describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Null:
    case YAML::NodeType::Undefined:
      return "nothing";
    case YAML::NodeType::Sequence:
      return "a sequence";
    case YAML::NodeType::Map:
      return "a mapping";
    case YAML::NodeType::Scalar:
      break;
  }
  // A NaN is named in words: no jointhb message contains "nan" (issue 20, item 4).
  if (const auto v = parse_number(node.Scalar()); v && std::isnan(*v)) return "not-a-number";
  return (node.Tag() == "!" ? "string '" : "'") + node.Scalar() + "'";
}

std::string Reader::list(const std::set<std::string>& names) {
  std::string text;
  for (const auto& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

}  // namespace jointhb::io::yaml
