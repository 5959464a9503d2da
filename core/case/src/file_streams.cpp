#include "graftnav/case/file_streams.h"

#include <memory>

namespace graftnav {

ImuPassFn imuFileStream(const std::string& path, const ImuReadOptions& options,
                        ReadReport* report) {
  return [path, options, report](const ImuBlockFn& block) {
    ImuBlockReader reader(path, options);
    ImuSeries samples;
    while (reader.next(&samples)) block(samples);
    if (report) *report = reader.report();
  };
}

namespace {
class GnssFileSource final : public GnssSource {
 public:
  GnssFileSource(const std::string& pos, const std::string& fixtype, const GnssReadPolicy& policy)
      : reader_(pos, fixtype, policy) {}
  bool next(GnssFix* fix) override { return reader_.next(fix); }

 private:
  GnssStreamReader reader_;
};
}  // namespace

GnssOpenFn gnssFileStream(const std::string& pos_path, const std::string& fixtype_path,
                          const GnssReadPolicy& policy) {
  return [pos_path, fixtype_path, policy]() -> std::unique_ptr<GnssSource> {
    return std::make_unique<GnssFileSource>(pos_path, fixtype_path, policy);
  };
}

}  // namespace graftnav
