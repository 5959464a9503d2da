#include "graftnav/parallel/worker_pool.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace graftnav {

int workerCount(std::size_t count, int jobs) {
  if (jobs < 0) throw std::invalid_argument("jobs must be >= 0, got " + std::to_string(jobs));
  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const std::size_t wanted = static_cast<std::size_t>(jobs > 0 ? jobs : hardware);
  return static_cast<int>(std::max<std::size_t>(1, std::min(count, wanted)));
}

void parallelFor(std::size_t count, int jobs, const std::function<void(std::size_t)>& work,
                 const ItemDoneFn& on_done) {
  const int workers = workerCount(count, jobs);
  std::atomic<std::size_t> next{0};
  std::size_t done = 0;  // guarded by lock
  std::mutex lock;
  std::exception_ptr failure;
  auto worker = [&]() {
    for (std::size_t i = next++; i < count; i = next++) {
      try {
        work(i);
        std::lock_guard<std::mutex> guard(lock);
        ++done;
        if (on_done) on_done(i, done);
      } catch (...) {  // from the item or from on_done: the guard above is released by now
        std::lock_guard<std::mutex> guard(lock);
        if (!failure) failure = std::current_exception();
        next = count;  // hand out no more items
        return;
      }
    }
  };
  if (workers == 1) {
    worker();
  } else {
    std::vector<std::thread> threads;
    threads.reserve(static_cast<std::size_t>(workers));
    for (int k = 0; k < workers; ++k) threads.emplace_back(worker);
    for (auto& t : threads) t.join();
  }
  if (failure) std::rethrow_exception(failure);
}

}  // namespace graftnav
