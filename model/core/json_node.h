// Reading JSON input (morphologies, scenarios, genomes) with the project's error convention: every value
// knows its field path ("fitness.terms[2].weight"), so every error names the file and the field, what was
// expected and what was found.
#pragma once

#include <Eigen/Core>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace orcs {

/// How deep JSON from outside may nest (arrays and objects within each other). Every JSON input — scenarios,
/// genomes, jobs, settings, column mappings, results read back — is parsed by ParseJson, and nothing orcs reads
/// needs more than a few levels; the bound keeps a hostile 100,000-deep nesting from exhausting the stack in the
/// recursive code that copies, prints and destroys JSON values (docs/formats.md, "Input limits").
inline constexpr int kMaxJsonDepth = 256;

/// Parses JSON text; malformed text is an InputError "source:line: malformed JSON: ...", and text nested deeper
/// than kMaxJsonDepth is an InputError "source:line: JSON nested deeper than 256 levels".
nlohmann::json ParseJson(const std::string& text, const std::string& source);

/// What a JSON value is, for "found ..." in messages: "the string \"abc\"", "the number 3", "an object".
std::string DescribeJson(const nlohmann::json& value);

/// A JSON value together with its field path. Holds references: the document and the source name must
/// outlive it.
class JsonNode {
 public:
  JsonNode(const nlohmann::json& value, std::string path, const std::string& source)
      : value_(value), path_(std::move(path)), source_(source) {}

  const nlohmann::json& value() const { return value_; }
  const std::string& path() const { return path_; }
  const std::string& source() const { return source_; }

  /// Throws InputError "source: field 'path' expected <expected>, found <found>".
  [[noreturn]] void Fail(const std::string& expected, const std::string& found) const;
  /// Fail(expected, DescribeJson(value())).
  [[noreturn]] void Fail(const std::string& expected) const { Fail(expected, DescribeJson(value_)); }

  /// A member that must be present (this must be an object).
  JsonNode At(const std::string& key) const;
  /// Whether this is an object with member `key`.
  bool Has(const std::string& key) const { return value_.is_object() && value_.contains(key); }
  /// Rejects members other than `allowed` and "comment" (typos must not pass silently).
  void ExpectOnly(std::initializer_list<std::string_view> allowed) const;
  /// The elements of an array.
  std::vector<JsonNode> Elements() const;
  /// The members of an object, in the document's order (nlohmann sorts keys: alphabetical).
  std::vector<std::pair<std::string, JsonNode>> Members() const;

  double Number(const std::string& what) const;  ///< a finite number
  int Integer(const std::string& what) const;    ///< an integer that fits an int
  std::uint64_t Unsigned(const std::string& what) const;  ///< a non-negative integer
  std::string String(const std::string& what) const;
  bool Bool(const std::string& what) const;
  Eigen::Vector3d Vector3(const std::string& what) const;  ///< an array of 3 finite numbers
  std::vector<double> Numbers(const std::string& what) const;  ///< an array of finite numbers

  /// Optional members with a fallback.
  double NumberOr(const std::string& key, double fallback, const std::string& what) const {
    return Has(key) ? At(key).Number(what) : fallback;
  }
  std::string StringOr(const std::string& key, const std::string& fallback, const std::string& what) const {
    return Has(key) ? At(key).String(what) : fallback;
  }

 private:
  std::string Child(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

  const nlohmann::json& value_;
  std::string path_;
  const std::string& source_;
};

}  // namespace orcs
