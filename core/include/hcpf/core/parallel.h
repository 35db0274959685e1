#pragma once
// The project's one worker pool: a parallel loop over independent items.

#include <cstddef>
#include <functional>

namespace hcpf {

// Calls body(i) once for every i in [0, count) on min(workers, count)
// threads, the calling thread among them. Items are handed out one at a time
// from a shared counter, so items whose run times differ 100x still keep every
// thread busy; which thread runs an item is not fixed, so a body must touch
// only item i's own state (results are then the same for any `workers`).
// If a body throws, no further item is started and the first exception is
// rethrown once every thread has finished. workers <= 1 runs in order on the
// calling thread.
void ParallelFor(size_t count, int workers, const std::function<void(size_t)>& body);

}  // namespace hcpf
