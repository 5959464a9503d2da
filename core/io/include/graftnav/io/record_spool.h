#pragma once
// Fixed-size records of doubles in a temporary binary file: written once, then read back in
// passes, from several threads at once, for as long as the spool lives. A series that a run
// reads many times (the reference IMU under every grafted realization, SOL_REF under every
// evaluation) then costs neither memory nor a new parse of its text file per pass, and a pass
// gives back exactly the doubles that were written. The file is unlinked as soon as it is
// created (in `directory`, or std::filesystem::temp_directory_path(), i.e. TMPDIR, when none is
// given), so nothing is left behind.
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace graftnav {

class RecordSpool {
 public:
  // Throws std::runtime_error naming the directory when the file cannot be created.
  explicit RecordSpool(std::size_t doubles_per_record, const std::string& directory = {});
  ~RecordSpool();
  RecordSpool(const RecordSpool&) = delete;
  RecordSpool& operator=(const RecordSpool&) = delete;

  // Appends one record (doubles_per_record values). Throws std::logic_error after finish(),
  // std::runtime_error when the disk is full.
  void append(const double* record);
  // Appends `count` records stored one after the other.
  void append(const double* records, std::size_t count);
  // Writes what is buffered; the spool is read-only from now on.
  void finish();

  std::size_t size() const { return records_; }
  std::size_t recordDoubles() const { return width_; }
  // Reads records [first, first + count) into *out (resized). Safe from several threads at
  // once after finish(); throws std::logic_error before it and std::out_of_range past the end.
  void read(std::size_t first, std::size_t count, std::vector<double>* out) const;

 private:
  void flush();

  std::string directory_;  // where the file is, for messages
  int fd_ = -1;
  std::size_t width_;
  std::size_t records_ = 0;
  bool finished_ = false;
  std::vector<double> buffer_;
};

// One pass over a finished spool, record by record, read in blocks of `block_records`. Keeps the
// spool alive; several passes may read one spool at once.
class RecordPass {
 public:
  explicit RecordPass(std::shared_ptr<const RecordSpool> spool, std::size_t block_records = 2048);
  // The next record (recordDoubles() values, valid until the next call), or nullptr at the end.
  const double* next();

 private:
  std::shared_ptr<const RecordSpool> spool_;
  std::size_t block_;
  std::vector<double> raw_;
  std::size_t begin_ = 0, loaded_ = 0, k_ = 0;
};

}  // namespace graftnav
