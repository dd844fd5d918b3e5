// The event queue: exactly one entry per disc, keyed by the time of that disc's earliest
// scheduled event. A disc's key is changed in place instead of pushing a new entry, so the queue
// never grows beyond N and holds no stale entries of its own; staleness of a *partner* is
// detected with collision counters (Lubachevsky 1991).
//
// Structure: a calendar of time buckets in front of a small heap (the O(1) queue of Paul,
// J. Comput. Phys. 221, 615 (2007)). The time axis is cut into buckets of width `width`; the
// entries of the current bucket (all keys before `horizon`) sit in an indexed 4-ary min-heap,
// those of the next `buckets` buckets in unsorted doubly linked lists (one per bucket, linked
// through per-disc arrays), the rest in an overflow list. Changing a key is an O(1) unlink and
// push in the common case (a disc's next event lies several buckets ahead); only the few
// entries of the current bucket pay heap operations, on a heap small enough to stay in cache.
// When the heap runs empty, the next bucket's list is moved into it. The width is chosen from
// the keys at assign() so that a bucket holds about kPerBucket entries, and re-chosen when a
// full turn of the calendar shows it is far off (the event rate changed).
//
// The 4-ary heap alone (one cache line per group of four children) cost ~25% of the event loop
// at N = 10^4 and ~33% at 10^5 (perf), its deep levels missing the caches; figures with
// billiard_bench in lib/src/engine/README-performance.md.
#pragma once

#include "billiard/memory.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace billiard {

enum class EventKind : int { DiscDisc, DiscWall, CellCrossing };

class EventQueue {
 public:
  struct Entry {  // 16 bytes: the key next to the disc, so a sift touches one array
    double time;
    int disc;
    int tag;  // carried along for the caller (the engine: the cell to prefetch for this event)
  };

  // n discs, keys `times` (size n) and tags `tags` (size n, or empty: all 0).
  void assign(const std::vector<double>& times, const std::vector<int>& tags = {}) {
    const int n = static_cast<int>(times.size());
    node_.assign(static_cast<std::size_t>(n), Node{});
    for (int d = 0; d < n; ++d) {
      node_[d].time = times[d];
      node_[d].tag = tags.empty() ? 0 : tags[d];
    }
    rebuild();
  }

  bool empty() const { return node_.empty(); }
  int size() const { return static_cast<int>(node_.size()); }

  // The earliest entry (the queue must not be empty).
  const Entry& top() {
    if (heap_size_ == 0) refill();
    return at(0);
  }
  double key(int disc) const { return node_[disc].time; }
  int tag(int disc) const { return node_[disc].tag; }

  // The smallest child of the heap's root: the likely next top if the top's key grows (the
  // caller prefetches its data). Call after top(); the top itself when the heap has one entry.
  const Entry& runner_up() const {
    const int n = heap_size_;
    if (n < 2) return at(0);
    int best = 1;
    for (int c = 2, last = std::min(kArity + 1, n); c < last; ++c) {
      if (at(c).time < at(best).time) best = c;
    }
    return at(best);
  }

  // Changes the key and the tag of `disc`.
  void update(int disc, double time, int tag) {
    node_[disc].tag = tag;
    update(disc, time);
  }
  void update(int disc, double time) {
    Node& node = node_[disc];
    node.time = time;
    const int k = node.slot;
    if (k >= 0 && time < horizon_) {  // stays in the heap
      const double old = at(k).time;
      at(k).time = time;
      at(k).tag = node.tag;
      if (time < old) {
        sift_up(k);
      } else {
        sift_down(k);
      }
      return;
    }
    if (k >= 0) {
      heap_erase(k);
    } else {
      unlink(disc);
    }
    insert(disc);
    // Far more entries in the current bucket than planned: the events came closer together
    // (the buckets are too wide; the heap would grow to hold everything). Re-plan, at most once
    // per size() changes so that a pile of equal keys cannot make it quadratic.
    if (++changes_ > size() && heap_size_ > kHeapLimit) rebuild();
  }

  // Heap order, every heap key before the horizon, every listed key in its bucket, and the
  // indices pointing back at their entries (for validation).
  bool valid() const {
    for (int k = 1; k < heap_size_; ++k) {
      if (at((k - 1) / kArity).time > at(k).time) return false;
    }
    for (int k = 0; k < heap_size_; ++k) {
      const Entry& e = at(k);
      const Node& node = node_[e.disc];
      if (node.slot != k || e.time != node.time || e.tag != node.tag) return false;
      if (!(e.time < horizon_) && horizon_ < std::numeric_limits<double>::infinity()) return false;
    }
    int listed = 0;
    for (int b = 0; b <= buckets_; ++b) {
      for (int d = head_[b]; d >= 0; d = node_[d].next) {
        ++listed;
        const Node& node = node_[d];
        if (node.slot >= 0 || !(node.time >= horizon_)) return false;
        if (b < buckets_ && (std::max(bucket_of(node.time), current_ + 1) & (buckets_ - 1)) != b) return false;
      }
    }
    return listed + heap_size_ == size();
  }

  std::size_t memory_bytes() const {
    return storage_.capacity() * sizeof(Entry) + node_.capacity() * sizeof(Node) + head_.capacity() * sizeof(int);
  }

 private:
  static constexpr int kArity = 4;
  static constexpr int kPad = 3;  // root at storage_[kPad]: each group of 4 children on one cache line
  static constexpr double kPerBucket = 4.0;  // entries per bucket aimed at
  static constexpr int kNone = -1;
  static constexpr int kHeapLimit = 1024;  // heap size that calls for narrower buckets

  Entry& at(int k) { return storage_[static_cast<std::size_t>(k) + kPad]; }
  const Entry& at(int k) const { return storage_[static_cast<std::size_t>(k) + kPad]; }

  // Absolute bucket index of a time t >= origin_ (truncation is the floor there; saturated for
  // far or infinite times).
  std::int64_t bucket_of(double t) const {
    const double b = (t - origin_) * inverse_width_;
    return b < 4.0e18 ? static_cast<std::int64_t>(b) : std::int64_t{4} << 60;
  }

  void insert(int disc) {
    const double t = node_[disc].time;
    // (horizon_ is infinite only when every key was at the last rebuild: then all go to the heap)
    if (t < horizon_ || horizon_ == std::numeric_limits<double>::infinity()) {
      heap_push(disc);
      return;
    }
    // At least the next bucket: rounding must not put a key into the bucket already drained.
    const std::int64_t b = std::max(bucket_of(t), current_ + 1);
    push_front(disc, b < current_ + buckets_ ? static_cast<int>(b & (buckets_ - 1)) : buckets_);
  }

  void push_front(int disc, int list) {
    const int first = head_[list];
    node_[disc].next = first;
    node_[disc].prev = -2 - list;  // a head: the list's index, encoded below -1
    if (first >= 0) node_[first].prev = disc;
    head_[list] = disc;
  }
  void unlink(int disc) {
    const int before = node_[disc].prev;
    const int after = node_[disc].next;
    if (before >= 0) {
      node_[before].next = after;
    } else {
      head_[-2 - before] = after;
    }
    if (after >= 0) node_[after].prev = before;
  }

  // The heap ran empty: move the next non-empty bucket into it, or re-plan the calendar.
  void refill() {
    std::int64_t turn = 0;
    while (heap_size_ == 0) {
      if (++turn > buckets_) {  // a whole turn of empty buckets: only the overflow is left
        rebuild();
        return;
      }
      ++current_;
      horizon_ = origin_ + static_cast<double>(current_ + 1) * width_;
      const int b = static_cast<int>(current_ & (buckets_ - 1));
      if (b == 0) {
        // A new turn of the calendar: overflow entries that now fall within reach move to
        // their buckets. If the last turn saw far more or fewer entries per bucket than
        // planned, the width no longer suits the event rate: re-plan.
        const double per_bucket = static_cast<double>(moved_) / buckets_;
        moved_ = 0;
        if (per_bucket > 8 * kPerBucket || per_bucket < kPerBucket / 8) {
          rebuild();
          return;
        }
        for (int d = head_[buckets_], after; d >= 0; d = after) {
          after = node_[d].next;
          if (bucket_of(node_[d].time) < current_ + buckets_) {
            unlink(d);
            insert(d);
          }
        }
      }
      for (int d = head_[b], after; d >= 0; d = after) {
        after = node_[d].next;
        heap_push(d);
        ++moved_;
      }
      head_[b] = kNone;
    }
  }

  // Plans the calendar from the keys: width from the spread of the finite keys, origin at the
  // earliest key, then files every entry.
  void rebuild() {
    const int n = size();
    double first = std::numeric_limits<double>::infinity();
    for (const Node& node : node_) first = std::min(first, node.time);
    double sum = 0.0;
    int finite = 0;
    for (const Node& node : node_) {
      const double t = node.time;
      if (std::isfinite(t)) {
        sum += t - first;
        ++finite;
      }
    }
    const double spread = finite > 0 ? sum / finite : 0.0;  // mean key distance ahead
    width_ = spread > 0 ? 2 * spread * kPerBucket / std::max(finite, 1) : 1.0;
    // Buckets over about 4 mean distances ahead (a power of two for a cheap modulo).
    buckets_ = 1;
    while (buckets_ < 64 || static_cast<double>(buckets_) * width_ < 4 * spread) {
      if (buckets_ >= (1 << 26)) break;
      buckets_ *= 2;
    }
    inverse_width_ = 1.0 / width_;
    origin_ = std::isfinite(first) ? first : 0.0;
    current_ = 0;
    horizon_ = std::isfinite(first) ? origin_ + width_ : std::numeric_limits<double>::infinity();
    moved_ = 0;
    changes_ = 0;
    storage_.assign(static_cast<std::size_t>(n) + kPad, Entry{0.0, -1, 0});
    head_.assign(static_cast<std::size_t>(buckets_) + 1, kNone);
    heap_size_ = 0;
    for (Node& node : node_) node.slot = node.next = node.prev = kNone;
    for (int d = 0; d < n; ++d) insert(d);
  }

  void heap_push(int disc) {
    const int k = heap_size_++;
    at(k) = {node_[disc].time, disc, node_[disc].tag};
    node_[disc].slot = k;
    sift_up(k);
  }
  void heap_erase(int k) {
    const int disc = at(k).disc;
    node_[disc].slot = kNone;
    const int last = --heap_size_;
    if (k == last) return;
    const Entry moved = at(last);
    const double old = at(k).time;
    at(k) = moved;
    node_[moved.disc].slot = k;
    if (moved.time < old) {
      sift_up(k);
    } else {
      sift_down(k);
    }
  }

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
  // Top-down sift; the smallest of four children chosen without branches.
  void sift_down(int k) {
    const int n = heap_size_;
    const Entry moving = at(k);
    while (true) {
      const int first = kArity * k + 1;
      if (first >= n) break;
      int child;
      if (first + kArity <= n) {
        const Entry* c = &at(first);
        const int a = c[1].time < c[0].time ? 1 : 0;
        const int b = c[3].time < c[2].time ? 3 : 2;
        child = first + (c[b].time < c[a].time ? b : a);
      } else {
        child = first;
        for (int c = first + 1; c < n; ++c) {
          if (at(c).time < at(child).time) child = c;
        }
      }
      if (moving.time <= at(child).time) break;
      place(k, at(child));
      k = child;
    }
    place(k, moving);
  }
  void place(int k, const Entry& entry) {
    at(k) = entry;
    node_[entry.disc].slot = k;
  }

  // Per disc: 32 bytes, half a cache line, so that a list operation touches one line per disc.
  struct alignas(32) Node {
    double time = 0.0;  // key
    int tag = 0;
    int slot = kNone;   // position in the heap, or kNone when in a list
    int next = kNone;   // list links; prev below -1 encodes the list's head (-2 - list)
    int prev = kNone;
  };
  BigVector<Node> node_;
  // The heap of the current bucket.
  BigVector<Entry> storage_;   // cache-line aligned
  int heap_size_ = 0;
  // The calendar.
  std::vector<int> head_;      // first disc of each bucket's list; [buckets_] = overflow
  int buckets_ = 1;
  double origin_ = 0.0;        // bucket b covers [origin_ + b width_, origin_ + (b + 1) width_)
  double width_ = 1.0;
  double inverse_width_ = 1.0;
  std::int64_t current_ = 0;   // the bucket whose entries are in the heap
  double horizon_ = 0.0;       // end of the current bucket
  std::int64_t moved_ = 0;     // entries moved into the heap during this turn
  int changes_ = 0;            // key changes since the last rebuild
};

}  // namespace billiard
