#include "libs/netsim/release_queue.h"

#include <algorithm>

namespace haptex::netsim {

ReleaseQueue::ReleaseQueue(std::size_t capacity) : capacity_(capacity) { heap_.reserve(capacity); }

bool ReleaseQueue::Later(const Entry& a, const Entry& b) {
  if (a.copy.release_ns != b.copy.release_ns) return a.copy.release_ns > b.copy.release_ns;
  return a.order > b.order;
}

bool ReleaseQueue::Push(const ScheduledCopy& copy) {
  if (heap_.size() >= capacity_) return false;
  heap_.push_back(Entry{copy, pushed_++});
  std::push_heap(heap_.begin(), heap_.end(), Later);
  return true;
}

ScheduledCopy ReleaseQueue::Pop() {
  std::pop_heap(heap_.begin(), heap_.end(), Later);
  const ScheduledCopy copy = heap_.back().copy;
  heap_.pop_back();
  return copy;
}

}  // namespace haptex::netsim
