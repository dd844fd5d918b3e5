// The event queue: an indexed 4-ary min-heap with exactly one entry per disc, keyed by the time
// of that disc's earliest scheduled event. A disc's key is changed in place (sift up or down)
// instead of pushing a new entry, so the heap never grows beyond N and holds no stale entries
// of its own; staleness of a *partner* is detected with collision counters (Lubachevsky 1991).
//
// Why this queue: it needs no tuning (a calendar queue needs a bucket width matched to the
// event rate) and its cost is O(log N) per update with a small constant. Four children per node
// instead of two: half the levels, and the four children of a node share one cache line.
// (Measured with billiard_bench: no significant difference from a binary heap at N = 10^4 and
// 10^5 on the development machine; kept because it is never worse.) The figures measured
// with billiard_bench are in lib/src/engine/README-performance.md.
#pragma once

#include "billiard/memory.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace billiard {

enum class EventKind : int { DiscDisc, DiscWall, CellCrossing };

class EventQueue {
 public:
  struct Entry {  // 16 bytes: the key next to the disc, so a sift touches one array
    double time;
    int disc;
  };

  // n discs, all keys set to `times` (size n), heap built bottom-up in O(n).
  void assign(const std::vector<double>& times) {
    const int n = static_cast<int>(times.size());
    size_ = n;
    storage_.assign(times.size() + kPad, Entry{0.0, -1});
    slot_.resize(times.size());
    for (int i = 0; i < n; ++i) at(i) = {times[i], i};
    for (int k = n >= 2 ? (n - 2) / kArity : -1; k >= 0; --k) sift_down(k);  // parents only
    for (int k = 0; k < n; ++k) slot_[at(k).disc] = k;
  }

  bool empty() const { return size_ == 0; }
  int size() const { return size_; }
  const Entry& top() const { return at(0); }
  double key(int disc) const { return at(slot_[disc]).time; }

  // Changes the key of `disc` and restores heap order.
  void update(int disc, double time) {
    const int k = slot_[disc];
    const double old = at(k).time;
    at(k).time = time;
    if (time < old) {
      sift_up(k);
    } else {
      sift_down(k);
    }
  }

  // Heap order holds and the slots point back at their entries (for validation).
  bool valid() const {
    for (int k = 1; k < size(); ++k) {
      if (at((k - 1) / kArity).time > at(k).time) return false;
    }
    for (int k = 0; k < size(); ++k) {
      if (slot_[at(k).disc] != k) return false;
    }
    return true;
  }

  std::size_t memory_bytes() const {
    return storage_.capacity() * sizeof(Entry) + slot_.capacity() * sizeof(int);
  }

 private:
  static constexpr int kArity = 4;
  // The root sits at storage_[kPad]: then the four children 4k+1 .. 4k+4 of every node occupy
  // storage_[4(k+1) .. 4(k+1)+3], exactly one 64-byte cache line of the aligned storage.
  static constexpr int kPad = 3;
  Entry& at(int k) { return storage_[static_cast<std::size_t>(k) + kPad]; }
  const Entry& at(int k) const { return storage_[static_cast<std::size_t>(k) + kPad]; }

  void sift_up(int k) {
    const Entry moving = at(k);
    while (k > 0) {
      const int parent = (k - 1) / kArity;
      if (at(parent).time <= moving.time) break;
      place(k, at(parent));
      k = parent;
    }
    place(k, moving);
  }
  void sift_down(int k) {
    const int n = size();
    const Entry moving = at(k);
    while (true) {
      const int first = kArity * k + 1;
      if (first >= n) break;
      // Smallest of up to four children (one cache line).
      int child = first;
      const int last = std::min(first + kArity, n);
      for (int c = first + 1; c < last; ++c) {
        if (at(c).time < at(child).time) child = c;
      }
      if (moving.time <= at(child).time) break;
      place(k, at(child));
      k = child;
    }
    place(k, moving);
  }
  void place(int k, const Entry& entry) {
    at(k) = entry;
    if (!slot_.empty()) slot_[entry.disc] = k;
  }

  BigVector<Entry> storage_;  // cache-line aligned (huge pages when large)
  BigVector<int> slot_;  // slot_[disc] = position of disc's entry in the heap
  int size_ = 0;
};

}  // namespace billiard
