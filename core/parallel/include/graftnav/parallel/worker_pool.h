#pragma once
// One worker pool for the whole tree: `count` independent items (navigations of one evaluation,
// tasks of a batch) run on a few threads, handed out in index order, each item's result written
// by the caller to its own slot. Nothing here knows what an item is.

#include <cstddef>
#include <functional>

namespace graftnav {

// Threads for `count` items: `jobs` when > 0, all hardware threads when 0; never more than the
// items, never fewer than one. Throws std::invalid_argument for jobs < 0.
int workerCount(std::size_t count, int jobs);

// Called after each item, one call at a time (under the pool's lock): the item's index and how
// many items have finished so far, this one included.
using ItemDoneFn = std::function<void(std::size_t index, std::size_t done)>;

// Calls work(i) for every i in [0, count) on workerCount(count, jobs) threads; items are taken in
// index order. The first exception a work item throws stops handing out items, the running items
// finish, and that exception is rethrown here (the items that never started are not run; their
// on_done is not called). With one worker the items run on the calling thread.
void parallelFor(std::size_t count, int jobs, const std::function<void(std::size_t)>& work,
                 const ItemDoneFn& on_done = {});

}  // namespace graftnav
