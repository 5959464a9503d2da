#include "graftnav/io/text_table.h"
#include "graftnav/io/file_errors.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace graftnav {

std::string readWholeFile(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw MissingFileError(path, path + ": cannot open file (missing or unreadable)");
  std::string data;
  long size = -1;
  if (std::fseek(f, 0, SEEK_END) == 0) {
    size = std::ftell(f);
    std::fseek(f, 0, SEEK_SET);
  }
  if (size > 0) {  // one read into the final buffer
    data.resize(static_cast<std::size_t>(size));
    data.resize(std::fread(data.data(), 1, data.size(), f));
  }
  char chunk[1 << 16];  // whatever is left (or everything, when the size is unknown)
  std::size_t n;
  while ((n = std::fread(chunk, 1, sizeof(chunk), f)) > 0) data.append(chunk, n);
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) throw std::runtime_error(path + ": read error");
  return data;
}

namespace {
std::size_t newlinesIn(const char* data, std::size_t size) {
  return static_cast<std::size_t>(std::count(data, data + size, '\n'));
}
}  // namespace

std::size_t countPhysicalLines(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw MissingFileError(path, path + ": cannot open file (missing or unreadable)");
  std::size_t n = 1;
  std::vector<char> chunk(std::size_t{1} << 20);
  std::size_t got;
  while ((got = std::fread(chunk.data(), 1, chunk.size(), f)) > 0)
    n += newlinesIn(chunk.data(), got);
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) throw std::runtime_error(path + ": read error");
  return n;
}

std::string quoteForMessage(std::string_view text, std::size_t max_chars) {
  std::string s = "'";
  if (text.size() > max_chars) {
    s.append(text.substr(0, max_chars));
    s += "...";
  } else {
    s.append(text);
  }
  s += "'";
  return s;
}

TextTableReader::TextTableReader(std::string path) : path_(std::move(path)) {
  buffer_ = readWholeFile(path_);
}

TextTableReader TextTableReader::streaming(std::string path, std::size_t chunk_bytes) {
  TextTableReader r;
  r.path_ = std::move(path);
  r.chunk_bytes_ = std::max<std::size_t>(chunk_bytes, 64);
  r.file_.reset(std::fopen(r.path_.c_str(), "rb"));
  if (!r.file_)
    throw MissingFileError(r.path_, r.path_ + ": cannot open file (missing or unreadable)");
  r.buffer_.reserve(2 * r.chunk_bytes_);
  return r;
}

void TextTableReader::readMore() {
  buffer_.erase(0, pos_);
  pos_ = 0;
  const std::size_t old = buffer_.size();
  buffer_.resize(old + chunk_bytes_);
  const std::size_t n = std::fread(buffer_.data() + old, 1, chunk_bytes_, file_.get());
  buffer_.resize(old + n);
  if (n < chunk_bytes_) {
    if (std::ferror(file_.get()) != 0) throw std::runtime_error(path_ + ": read error");
    file_.reset();
  }
}

namespace {
inline bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r'; }
}  // namespace

bool TextTableReader::next() {
  for (;;) {
    // Streaming: make sure a whole line (or the rest of the file) is in the buffer.
    while (file_ && std::memchr(buffer_.data() + pos_, '\n', buffer_.size() - pos_) == nullptr)
      readMore();
    const std::size_t size = buffer_.size();
    if (pos_ >= size) break;
    const char* const data = buffer_.data();
    const char* start = data + pos_;
    const char* nl = static_cast<const char*>(std::memchr(start, '\n', size - pos_));
    const char* end = nl ? nl : data + size;
    pos_ = nl ? static_cast<std::size_t>(nl - data) + 1 : size;
    ++line_number_;
    if (end > start && end[-1] == '\r') --end;
    line_ = std::string_view(start, static_cast<std::size_t>(end - start));

    // Parse numbers directly; a token must end at a blank or at the end of the line.
    const char* p = start;
    while (p < end && isBlank(*p)) ++p;
    if (p == end || *p == '#') continue;  // blank or comment line
    column_count_ = 0;
    while (p < end) {
      if (column_count_ >= kMaxColumns)
        fail("too many columns (more than " + std::to_string(kMaxColumns) + ") in line " +
             quoteForMessage(line_));
      const char* tok = p;
      const char* num = (*p == '+') ? p + 1 : p;
      double v = 0.0;
      const auto res = std::from_chars(num, end, v);
      const char* stop = res.ptr;
      if (res.ec == std::errc::result_out_of_range) {
        while (stop < end && !isBlank(*stop)) ++stop;
        v = std::strtod(std::string(tok, stop).c_str(),
                        nullptr);  // overflow/underflow: inf or denormal
      } else if (res.ec != std::errc() || (stop < end && !isBlank(*stop))) {
        stop = tok;
        while (stop < end && !isBlank(*stop)) ++stop;
        fail("column " + std::to_string(column_count_ + 1) + ": " +
             quoteForMessage(std::string_view(tok, static_cast<std::size_t>(stop - tok))) +
             " is not a number");
      }
      tokens_[column_count_] = std::string_view(tok, static_cast<std::size_t>(stop - tok));
      values_[column_count_++] = v;
      p = stop;
      while (p < end && isBlank(*p)) ++p;
    }
    return true;
  }
  column_count_ = 0;
  line_ = {};
  return false;
}

void TextTableReader::fail(const std::string& what) const {
  throw std::runtime_error(path_ + ":" + std::to_string(line_number_) + ": " + what);
}

void TextTableReader::requireColumns(int count_a, int count_b, const char* format_name) const {
  if (column_count_ == count_a || column_count_ == count_b) return;
  std::string expected = std::to_string(count_a);
  if (count_b != count_a) expected += " or " + std::to_string(count_b);
  fail(std::string(format_name) + " line has " + std::to_string(column_count_) +
       " columns, expected " + expected + ": " + quoteForMessage(line_));
}

void TextTableReader::requireFinite(const char* const* column_names) const {
  for (int i = 0; i < column_count_; ++i) {
    if (!std::isfinite(values_[i])) {
      fail(std::string(column_names[i]) + " (column " + std::to_string(i + 1) + ") is " +
           quoteForMessage(tokens_[i]) + ", not a finite number");
    }
  }
}

int TextTableReader::integerValue(int column, const char* column_name) const {
  const double v = values_[column];
  if (!std::isfinite(v) || v != std::floor(v) || std::fabs(v) > 2e9)
    fail(std::string(column_name) + " (column " + std::to_string(column + 1) + ") is " +
         quoteForMessage(tokens_[column]) + ", not an integer");
  return static_cast<int>(v);
}

std::size_t TextTableReader::physicalLineCount() const {
  if (chunk_bytes_ > 0)
    throw std::logic_error(path_ + ": physicalLineCount() of a streaming reader");
  return 1 + newlinesIn(buffer_.data(), buffer_.size());
}

TimeOrderGuard::TimeOrderGuard(ReadRule duplicate_rule, ReadRule backwards_rule,
                               int max_consecutive_drops)
    : duplicate_rule_(duplicate_rule),
      backwards_rule_(backwards_rule),
      max_consecutive_drops_(max_consecutive_drops) {
  requireRule(duplicate_rule, {ReadRule::kError, ReadRule::kRepair}, "duplicate_stamp");
  requireRule(backwards_rule, {ReadRule::kError, ReadRule::kRepair}, "backwards_stamp");
}

bool TimeOrderGuard::accept(const TextTableReader& r, double t_s, int time_column,
                            ReadReport& report) {
  const int n = r.columnCount();
  if (has_prev_ && !(t_s > t_prev_)) {
    const std::string t_text(r.token(time_column));
    const std::string prev_text(prev_time_text_);
    const std::string where = " (line " + std::to_string(prev_line_) + ")";
    if (t_s == t_prev_) {
      bool identical = n == prev_count_;
      for (int i = 0; identical && i < n; ++i) identical = r.value(i) == prev_values_[i];
      if (duplicate_rule_ == ReadRule::kError || !identical) {
        r.fail("time " + t_text + " is not after previous " + prev_text + where +
               (identical ? ": duplicated line" : ": duplicated time stamp with different values"));
      }
      report.note(ReadCondition::kDuplicateStamp, r.lineNumber(),
                  "time " + t_text + " repeats line " + std::to_string(prev_line_) +
                      " identically: dropped");
    } else {
      if (backwards_rule_ == ReadRule::kError)
        r.fail("time " + t_text + " is not after previous " + prev_text + where);
      if (++consecutive_drops_ > max_consecutive_drops_)
        r.fail("time " + t_text + " is not after previous " + prev_text + where + ": more than " +
               std::to_string(max_consecutive_drops_) +
               " lines in a row go backwards; not repairable");
      report.note(ReadCondition::kBackwardsStamp, r.lineNumber(),
                  "time " + t_text + " is before previous " + prev_text + where + ": dropped");
    }
    ++report.records_dropped;
    return false;
  }
  has_prev_ = true;
  t_prev_ = t_s;
  prev_line_ = r.lineNumber();
  prev_count_ = n;
  prev_time_text_ = r.token(time_column);
  for (int i = 0; i < n; ++i) prev_values_[i] = r.value(i);
  consecutive_drops_ = 0;
  return true;
}

void requireRule(ReadRule rule, std::initializer_list<ReadRule> allowed, const char* field_name) {
  std::string list;
  for (ReadRule a : allowed) {
    if (a == rule) return;
    if (!list.empty()) list += ", ";
    list += toString(a);
  }
  throw std::invalid_argument(std::string(field_name) + ": rule '" + toString(rule) +
                              "' is not allowed here (allowed: " + list + ")");
}

const char* toString(ReadRule rule) {
  switch (rule) {
    case ReadRule::kError:
      return "error";
    case ReadRule::kWarn:
      return "warn";
    case ReadRule::kRepair:
      return "repair";
  }
  return "?";
}

const char* toString(ReadCondition condition) {
  switch (condition) {
    case ReadCondition::kUnevenInterval:
      return "uneven sample interval";
    case ReadCondition::kGap:
      return "gap";
    case ReadCondition::kDuplicateStamp:
      return "duplicated time stamp";
    case ReadCondition::kBackwardsStamp:
      return "backwards time stamp";
    case ReadCondition::kOffWholeSecond:
      return "epoch off whole seconds";
    case ReadCondition::kZeroStd:
      return "zero standard deviation";
    case ReadCondition::kUnmatchedEpoch:
      return "unmatched fix-type epoch";
    case ReadCondition::kCount:
      break;
  }
  return "?";
}

bool ReadReport::clean() const {
  for (int c : counts)
    if (c != 0) return false;
  return true;
}

void ReadReport::note(ReadCondition c, int line, std::string text) {
  const int n = ++counts[static_cast<int>(c)];
  if (n <= max_examples_per_condition) examples.push_back({c, line, std::move(text)});
}

std::string ReadReport::summary() const {
  if (clean()) return {};
  std::string s = path + ": " + std::to_string(data_lines) + " lines, " +
                  std::to_string(records_kept) + " records kept, " +
                  std::to_string(records_dropped) + " dropped\n";
  for (int i = 0; i < kReadConditionCount; ++i) {
    if (counts[i] == 0) continue;
    const auto c = static_cast<ReadCondition>(i);
    s += "  " + std::to_string(counts[i]) + " x " + toString(c) + "\n";
    for (const auto& ex : examples)
      if (ex.condition == c) s += "    line " + std::to_string(ex.line) + ": " + ex.text + "\n";
  }
  return s;
}

}  // namespace graftnav
