#include "model/core/value_logger.h"

#include <algorithm>
#include <limits>
#include <new>
#include <string>
#include <utility>

#include "model/core/error.h"
#include "model/core/text.h"

namespace orcs {
namespace {

// Suffixes of the columns a value of each type spreads over ("" = one column named by the path).
std::vector<std::string_view> ComponentSuffixes(ValueType type) {
  switch (type) {
    case ValueType::kVector3: return {".x", ".y", ".z"};
    case ValueType::kQuaternion: return {".w", ".x", ".y", ".z"};
    case ValueType::kColor: return {".r", ".g", ".b", ".a"};
    default: return {""};
  }
}

// Appends a string field, quoted when it holds a separator or a quote (RFC 4180).
void AppendStringField(std::string& row, const std::string& field) {
  if (field.find_first_of(",\"\n\r") == std::string::npos) {
    row += field;
    return;
  }
  row += '"';
  for (char c : field) {
    if (c == '"') row += '"';
    row += c;
  }
  row += '"';
}

void AppendValue(std::string& row, const Value& value) {
  switch (value.type()) {
    case ValueType::kBool: row += value.as_bool() ? "1" : "0"; break;
    case ValueType::kInt: row += std::to_string(value.as_int()); break;
    case ValueType::kDouble: row += text::FormatDouble(value.as_double()); break;
    case ValueType::kString: AppendStringField(row, value.as_string()); break;
    case ValueType::kColor: {
      const Color c = value.as_color();
      row += std::to_string(c.r) + ',' + std::to_string(c.g) + ',' + std::to_string(c.b) + ',' + std::to_string(c.a);
      break;
    }
    case ValueType::kVector3: {
      const auto& v = value.as_vector3();
      row += text::FormatDouble(v.x()) + ',' + text::FormatDouble(v.y()) + ',' + text::FormatDouble(v.z());
      break;
    }
    case ValueType::kQuaternion: {
      const auto q = value.as_quaternion();
      row += text::FormatDouble(q.w()) + ',' + text::FormatDouble(q.x()) + ',' + text::FormatDouble(q.y()) + ',' +
             text::FormatDouble(q.z());
      break;
    }
  }
}

}  // namespace

ValueLogger::ValueLogger(const VariableRepository& repository, const std::vector<std::string>& regular_expressions)
    : repository_(repository) {
  for (const std::string& expression : regular_expressions) {
    const std::vector<int> matched = repository.Match(expression);
    if (matched.empty()) throw InputError("--log " + text::Quote(expression) + ": matches no repository value");
    ids_.insert(ids_.end(), matched.begin(), matched.end());
  }
  std::sort(ids_.begin(), ids_.end());
  ids_.erase(std::unique(ids_.begin(), ids_.end()), ids_.end());
}

std::vector<std::string> ValueLogger::column_names() const {
  std::vector<std::string> names{"time"};
  for (int id : ids_) {
    for (std::string_view suffix : ComponentSuffixes(repository_.value(id).type())) {
      names.push_back(repository_.path(id) + std::string(suffix));
    }
  }
  return names;
}

void ValueLogger::Open(const std::string& path, const std::vector<std::string>& comments, std::size_t max_bytes,
                       std::string why) {
  file_.reset();  // an earlier, unfinished file first: it shares the temporary name and would remove ours
  file_ = std::make_unique<AtomicFile>(path);
  out_ = &file_->stream();
  max_bytes_ = max_bytes;
  truncated_ = false;
  written_ = 0;
  why_truncated_ = why.empty() ? "it reached its bound of " + std::to_string(max_bytes) + " bytes" : std::move(why);
  WriteHeader(comments);
}

void ValueLogger::OpenInMemory(const std::vector<std::string>& comments, std::size_t max_bytes, std::string why) {
  file_.reset();
  memory_.str("");
  out_ = &memory_;
  max_bytes_ = max_bytes;
  truncated_ = false;
  written_ = 0;
  why_truncated_ = why.empty() ? "it reached its bound of " + std::to_string(max_bytes) + " bytes" : std::move(why);
  WriteHeader(comments);
}

void ValueLogger::WriteHeader(const std::vector<std::string>& comments) {
  std::string header;
  for (const std::string& comment : comments) header += "# " + comment + '\n';
  header += "# columns: ";
  const std::vector<std::string> names = column_names();
  for (size_t i = 0; i < names.size(); ++i) header += (i ? "," : "") + names[i];
  header += '\n';
  *out_ << header;
  written_ += header.size();
}

void ValueLogger::Sample(double time) {
  if (truncated_) return;
  row_.clear();
  row_ += text::FormatDouble(time);
  for (int id : ids_) {
    row_ += ',';
    AppendValue(row_, repository_.value(id));
  }
  row_ += '\n';
  if (written_ + row_.size() > max_bytes_) {
    const std::string line = "# log truncated at time " + text::FormatDouble(time) + " s: " + why_truncated_ + '\n';
    *out_ << line;
    written_ += line.size();
    truncated_ = true;
    return;
  }
  *out_ << row_;
  written_ += row_.size();
  // A string stream fails silently when it cannot grow: say so, rather than hand back a log with rows missing.
  if (out_ == &memory_ && !memory_) throw std::bad_alloc();
}

void ValueLogger::Finish() {
  if (file_) file_->Commit();
  file_.reset();
  out_ = nullptr;
}

std::string ValueLogger::TakeText() { return std::move(memory_).str(); }

}  // namespace orcs
