#pragma once
// Fast reader of whitespace-separated numeric text tables (the i2Nav formats of dataset.md).
// By default the whole file is read in one go; TextTableReader::streaming() reads it in chunks so
// that memory does not grow with the file. Numbers are parsed with std::from_chars; no iostreams.
// Blank lines and lines whose first non-blank character is '#' are skipped (dataset files have
// none, but hand-edited slices may). Every error names "path:line: ..." and the offending text.

#include <array>
#include <cstdio>
#include <initializer_list>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace graftnav {

// Reads a whole file into memory; throws std::runtime_error "path: cannot open ..." when missing.
std::string readWholeFile(const std::string& path);

// Number of physical lines of a file (1 + its newlines, as TextTableReader::physicalLineCount),
// read in chunks: the size to reserve before a streaming read. Throws std::runtime_error when the
// file cannot be read.
std::size_t countPhysicalLines(const std::string& path);

class TextTableReader {
 public:
  static constexpr int kMaxColumns = 16;

  // Reads the file; throws std::runtime_error when it cannot be opened.
  explicit TextTableReader(std::string path);
  // Reads the file in chunks of about chunk_bytes (a line longer than that is still read whole):
  // memory is one chunk plus one line, whatever the file's length. Lines, tokens and line numbers
  // are the same as the whole-file reader's. Throws std::runtime_error when it cannot be opened.
  static TextTableReader streaming(std::string path,
                                   std::size_t chunk_bytes = std::size_t{1} << 20);

  // Advances to the next data line and parses its numbers. Returns false at the end of the file.
  // Throws (naming path, line and token) when a token is not a number or the line has more than
  // kMaxColumns columns. Values may be NaN/inf here; callers decide (see requireFinite()).
  bool next();

  int lineNumber() const { return line_number_; }
  int columnCount() const { return column_count_; }
  double value(int column) const { return values_[column]; }
  const double* values() const { return values_.data(); }
  std::string_view lineText() const { return line_; }
  std::string_view token(int column) const { return tokens_[column]; }
  const std::string& path() const { return path_; }
  // Number of physical lines in the file (an upper bound of the data lines, for reserve()).
  // Whole-file reader only: throws std::logic_error on a streaming reader.
  std::size_t physicalLineCount() const;

  // Throws std::runtime_error "path:line: <what>".
  [[noreturn]] void fail(const std::string& what) const;
  // Throws unless the line has one of the two column counts (pass the same twice for one).
  void requireColumns(int count_a, int count_b, const char* format_name) const;
  // Throws naming the column and its text when a value is NaN or infinite.
  void requireFinite(const char* const* column_names) const;
  // Returns the value of a column that must hold an integer (e.g. a GNSS week); throws otherwise.
  int integerValue(int column, const char* column_name) const;

 private:
  struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  TextTableReader() = default;
  // Streaming: drops the consumed part of the buffer and appends the next chunk; closes the file
  // at its end. Throws std::runtime_error on a read error.
  void readMore();

  std::string path_;
  std::string buffer_;
  std::unique_ptr<std::FILE, FileCloser> file_;  // open only while streaming
  std::size_t chunk_bytes_ = 0;
  std::size_t pos_ = 0;
  int line_number_ = 0;
  int column_count_ = 0;
  std::string_view line_;
  std::array<double, kMaxColumns> values_{};
  std::array<std::string_view, kMaxColumns> tokens_{};
};

// ---- Robust reading of real files: per condition a rule, and a report of what was seen.

// What a reader does when it meets a condition. Not every rule fits every condition; the policy
// structs (ImuReadPolicy, GnssReadPolicy, NavReadPolicy) say which, and validate() rejects others.
enum class ReadRule {
  kError,   // throw std::runtime_error naming file, line and value
  kWarn,    // keep the data as it is, count the condition and keep the first examples
  kRepair,  // apply the stated repair (drop an identical duplicate, floor a zero std, ...), counted
};
const char* toString(ReadRule rule);

enum class ReadCondition {
  kUnevenInterval,  // sample interval off the nominal one by more than the tolerance
  kGap,             // sample interval longer than gap_factor times the nominal one
  kDuplicateStamp,  // time equal to the previous record's
  kBackwardsStamp,  // time before the previous record's
  kOffWholeSecond,  // GNSS epoch not on a whole second (counted only)
  kZeroStd,         // GNSS standard deviation of zero
  kUnmatchedEpoch,  // a gnss_fixtype.txt epoch with no .pos epoch at the same time (or vice versa)
  kCount
};
constexpr int kReadConditionCount = static_cast<int>(ReadCondition::kCount);
const char* toString(ReadCondition condition);

struct ReadExample {
  ReadCondition condition = ReadCondition::kGap;
  int line = 0;      // 1-based line number in the file
  std::string text;  // what was seen, e.g. "dt 0.0300 s = 3.00 x nominal 0.0100 s"
};

// What a reader met and did. Nothing is dropped without being counted here.
struct ReadReport {
  std::string path;
  int data_lines = 0;       // data lines parsed
  int records_kept = 0;     // records returned
  int records_dropped = 0;  // lines dropped by a repair (each also counted under its condition)
  std::array<int, kReadConditionCount> counts{};
  std::vector<ReadExample> examples;  // first max_examples_per_condition of each condition
  int max_examples_per_condition = 5;

  int count(ReadCondition c) const { return counts[static_cast<int>(c)]; }
  bool clean() const;  // no condition met
  void note(ReadCondition c, int line, std::string text);
  // Multi-line human-readable summary ("path: 3 gaps (warn) ... e.g. line 123: ..."); empty when clean.
  std::string summary() const;
};

// Checks that record times strictly increase and applies the duplicate/backwards rules:
//   duplicated stamp: kError -> throw; kRepair -> drop the line when every value equals the
//     previous kept line's (a differing duplicate is always an error);
//   backwards stamp: kError -> throw; kRepair -> drop the line (at most max_consecutive_drops in a
//     row, beyond that the file is not repairable and it throws).
// Every drop is counted in the report. Only kError and kRepair are valid rules here.
class TimeOrderGuard {
 public:
  TimeOrderGuard(ReadRule duplicate_rule, ReadRule backwards_rule, int max_consecutive_drops = 100);
  // Returns true to keep the reader's current line (then it becomes "previous"), false to drop it.
  bool accept(const TextTableReader& reader, double t_s, int time_column, ReadReport& report);

 private:
  ReadRule duplicate_rule_, backwards_rule_;
  int max_consecutive_drops_;
  bool has_prev_ = false;
  double t_prev_ = 0.0;
  int prev_line_ = 0;
  int prev_count_ = 0;
  std::string prev_time_text_;  // a copy: a streaming reader's buffer moves
  std::array<double, TextTableReader::kMaxColumns> prev_values_{};
  int consecutive_drops_ = 0;
};

// Throws std::invalid_argument "<policy>.<field>: rule '<rule>' is not allowed (allowed: ...)".
void requireRule(ReadRule rule, std::initializer_list<ReadRule> allowed, const char* field_name);

// Short file name used in messages is the path as given; this shortens a long line for messages.
std::string quoteForMessage(std::string_view text, std::size_t max_chars = 120);

}  // namespace graftnav
