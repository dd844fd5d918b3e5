// The event queue: one key per disc, the time of that disc's earliest scheduled event; the
// caller asks for the disc with the smallest key, pops it, and changes keys. Staleness of a
// *partner* is detected by the engine with collision counters (Lubachevsky 1991); staleness of
// the queue's own entries is detected here, lazily.
//
// Structure: a calendar of time buckets in front of a small heap (the O(1) queue of Paul,
// J. Comput. Phys. 221, 615 (2007)). The time axis is cut into buckets of width `width`; the
// entries of the current bucket (all keys before `horizon`) sit in a 4-ary min-heap, those of the
// next `buckets` buckets in unsorted chunks of three entries (one 64-byte chunk per bucket, more
// chained from a pool when it fills), the rest in an overflow list. When the heap runs empty, the
// next bucket's chunks are moved into it. The width is chosen from the keys so that a bucket
// holds about kPerBucket entries, and re-chosen when a turn of the calendar shows it is far off.
//
// Lazy deletion: the keys live with the caller (the engine: the earlier of each disc's predicted
// contact and cell crossing), read through `Keys`. Changing a disc's key files a new entry
// (time, disc, tag); the old entry stays where it is. An entry is current while its time equals
// its disc's key; others are dropped when they reach the top of the heap (or at a turn of the
// calendar, for the overflow list). Two current entries of one disc (the key changed and came
// back to the same time) are harmless: both say "this disc's event is due at this time", and the
// caller re-keys the disc when it handles the first. So a key change is one append to a bucket's
// chunk, instead of unlinking from a list and fixing the heap positions of the entries it moves
// (each a cache miss at large N).
//
// Hiding memory latency (the bound on speed from N ~ 10^5 on): an append to a bucket is not done
// at once; its chunk is prefetched and the entry waits in a short pending list until the next
// top() after the one that follows (or until a bucket is moved into the heap, which appends all
// pending entries first), so the chunk has arrived by then. A bucket holds several chunks
// chained one behind the other (about four when it is drained, at large N), and each link is
// known only once the chunk before it has arrived: so while one bucket is being handled, the
// next one's chain is walked one chunk per top(), each chunk prefetched a top() before it is
// read, and the caller is told (Keys::prefetch) which entries are coming: they are handled
// several events later. When a bucket is moved into the heap, the caller is told about the
// entries the walk did not reach (entries filed after it passed were just computed by the caller,
// their data still in its cache). Measured with billiard_bench, figures in
// lib/DESIGN.md.
//
// Keys: a small copyable object with `double key(int disc) const` and
// `void prefetch(int disc, int tag) const` (a hint; may do nothing). VectorKeys reads a
// std::vector.
#pragma once

#include "memory.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace billiard {

// Keys held in a vector by the caller (tests, small tools).
struct VectorKeys {
  const std::vector<double>* keys = nullptr;
  double key(int disc) const { return (*keys)[static_cast<std::size_t>(disc)]; }
  void prefetch(int, int) const {}
};

template <class Keys>
class CalendarQueue {
 public:
  struct Entry {  // 16 bytes: four to a cache line
    double time;
    int disc;
    int tag;  // carried along for the caller (the engine: the cell to prefetch for this event)
  };

  CalendarQueue() = default;
  explicit CalendarQueue(const Keys& keys) : keys_(keys) {}
  // Where the keys are read (set again if the caller's array moved).
  void set_keys(const Keys& keys) { keys_ = keys; }

  // n discs, one entry each with its current key, tags `tags` (size n, or empty: all 0).
  void assign(int n, const std::vector<int>& tags = {}) {
    size_ = n;
    std::vector<Entry> entries(static_cast<std::size_t>(n));
    for (int d = 0; d < n; ++d) entries[d] = Entry{keys_.key(d), d, tags.empty() ? 0 : tags[d]};
    rebuild(entries);
  }

  bool empty() const { return size_ == 0; }
  int size() const { return size_; }

  // The current entry with the smallest key (the queue must not be empty). It stays in the queue
  // until pop().
  const Entry& top() {
    // The appends of the update() calls before the previous top(): their chunks have arrived.
    append_pending(waiting_);
    waiting_ = pending_;
    walk_next_bucket();
    while (true) {
      if (heap_size_ == 0) refill();
      if (heap_size_ == 0) return kNothing;  // (only when no disc was assigned)
      const Entry& e = at(0);
      if (keys_.key(e.disc) == e.time) return e;
      heap_pop();  // superseded by a later key change
    }
  }
  // Removes the entry top() returned; the caller then gives its disc a new key with update().
  void pop() { heap_pop(); }

  // The likely next top, called after pop() (the caller prefetches its data): the heap's first
  // current entry, or nullptr when the heap must be refilled first. `changing` is a disc whose
  // key the caller is about to change (the partner of a collision being handled; -1 for none):
  // its entries will be superseded. Superseded entries, and those of `changing`, are dropped
  // from the front of the heap here, as top() would drop them. (Without this the guess was wrong
  // for 4 events in 10 at area fraction 0.5: the front entry was most often the partner's own
  // entry for the same collision.)
  const Entry* upcoming(int changing = kNone) {
    while (heap_size_ > 0 && (at(0).disc == changing || keys_.key(at(0).disc) != at(0).time)) heap_pop();
    return heap_size_ > 0 ? &at(0) : nullptr;
  }

  // Files `disc`'s new key `time`, which the caller has already stored where Keys reads it.
  void update(int disc, double time, int tag = 0) {
    file(Entry{time, disc, tag});
    // Far more entries in the current bucket than planned: the events came closer together
    // (the buckets are too wide). Re-plan, at most once per size() changes so that a pile of
    // equal keys cannot make it quadratic.
    if (++changes_ > size() && heap_size_ > kHeapLimit) rebuild(collect());
  }

  // Heap order, every heap entry before the horizon, every chunk entry in its bucket and after
  // the horizon, and a current entry for every disc (for validation).
  bool valid() const {
    const bool bounded = horizon_ < std::numeric_limits<double>::infinity();
    std::vector<char> seen(static_cast<std::size_t>(size_), 0);
    auto note = [&](const Entry& e) {
      if (e.disc < 0 || e.disc >= size()) return false;
      if (keys_.key(e.disc) == e.time) seen[e.disc] = 1;
      return true;
    };
    for (int k = 0; k < heap_size_; ++k) {
      const Entry& e = at(k);
      if (k > 0 && at((k - 1) / kArity).time > e.time) return false;
      if (bounded && !(e.time < horizon_)) return false;
      if (!note(e)) return false;
    }
    for (int b = 0; b < buckets_; ++b) {
      for (int c = b; c >= 0; c = chunks_[c].next) {
        for (int k = 0; k < chunks_[c].count; ++k) {
          const Entry& e = chunks_[c].entry[k];
          if (!(e.time >= horizon_) || (std::max(bucket_of(e.time), current_ + 1) & (buckets_ - 1)) != b) return false;
          if (!note(e)) return false;
        }
      }
    }
    for (int k = 0; k < pending_; ++k) {
      const Entry& e = pending_entry_[k];
      if (!(e.time >= horizon_) || (std::max(bucket_of(e.time), current_ + 1) & (buckets_ - 1)) != pending_bucket_[k]) return false;
      if (!note(e)) return false;
    }
    for (const Entry& e : overflow_) {
      if (!(e.time >= horizon_) || !note(e)) return false;
    }
    return std::all_of(seen.begin(), seen.end(), [](char s) { return s != 0; });
  }

  std::size_t memory_bytes() const {
    return storage_.capacity() * sizeof(Entry) + chunks_.capacity() * sizeof(Chunk) +
           free_.capacity() * sizeof(int) + overflow_.capacity() * sizeof(Entry);
  }

  // Every member but the keys, for saving a simulation and loading it back (snapshot.cpp):
  // `io` writes or reads each in turn. All of them, since the order in which equal keys come out
  // depends on where each entry sits.
  template <class Io>
  void transfer(Io& io) {
    const auto entry = [&io](Entry& e) {
      io(e.time);
      io(e.disc);
      io(e.tag);
    };
    io(size_);
    io.sequence(storage_, sizeof(Entry), entry);
    io(heap_size_);
    io.check(heap_size_ == 0 || (heap_size_ > 0 && static_cast<std::size_t>(heap_size_) + kPad <= storage_.size()),
             "queue heap size");
    io.sequence(chunks_, 3 * sizeof(Entry) + 2 * sizeof(int), [&](Chunk& chunk) {
      for (Entry& e : chunk.entry) entry(e);
      io(chunk.count);
      io(chunk.next);
    });
    io(free_);
    io.sequence(overflow_, sizeof(Entry), entry);
    io(pending_);
    io.check(pending_ >= 0 && pending_ <= kPending, "queue pending count");
    for (int k = 0; k < pending_; ++k) {
      entry(pending_entry_[k]);
      io(pending_bucket_[k]);
    }
    io(waiting_);
    io(walker_);
    io(buckets_);
    io(origin_);
    io(width_);
    io(inverse_width_);
    io(current_);
    io(horizon_);
    io(moved_);
    io(changes_);
  }

 private:
  static constexpr int kArity = 4;
  static constexpr int kPad = 3;  // root at storage_[kPad]: each group of 4 children on one cache line
  static constexpr double kPerBucket = 3.0;  // current entries per bucket aimed at
  static constexpr int kNone = -1;
  static constexpr int kHeapLimit = 1024;  // heap size that calls for narrower buckets
  static constexpr Entry kNothing{std::numeric_limits<double>::infinity(), kNone, 0};

  // One bucket's entries, or the continuation of a bucket that holds more than three.
  struct alignas(64) Chunk {
    Entry entry[3];
    int count = 0;
    int next = kNone;  // the next chunk of the same bucket
  };

  Entry& at(int k) { return storage_[static_cast<std::size_t>(k) + kPad]; }
  const Entry& at(int k) const { return storage_[static_cast<std::size_t>(k) + kPad]; }

  // Absolute bucket index of a time t >= origin_ (truncation is the floor there; saturated for
  // far or infinite times).
  std::int64_t bucket_of(double t) const {
    const double b = (t - origin_) * inverse_width_;
    return b < 4.0e18 ? static_cast<std::int64_t>(b) : std::int64_t{4} << 60;
  }

  // Files an entry: into the heap if it falls in the current bucket, else into its bucket or the
  // overflow list.
  void file(const Entry& e) {
    // (horizon_ is infinite only when every key was at the last rebuild: then all go to the heap)
    if (e.time < horizon_ || horizon_ == std::numeric_limits<double>::infinity()) {
      keys_.prefetch(e.disc, e.tag);  // (due within this bucket: soon)
      heap_push(e);
      return;
    }
    // At least the next bucket: rounding must not put a key into the bucket already drained.
    const std::int64_t b = std::max(bucket_of(e.time), current_ + 1);
    if (b < current_ + buckets_) {
      const int bucket = static_cast<int>(b & (buckets_ - 1));
      if (pending_ == kPending) append_pending(pending_);
      prefetch_line(&chunks_[bucket]);
      pending_bucket_[pending_] = bucket;
      pending_entry_[pending_++] = e;
    } else {
      overflow_.push_back(e);
    }
  }

  void append(int bucket, const Entry& e) {
    Chunk* chunk = &chunks_[bucket];
    if (chunk->count == 3) {
      // Full: move its entries to a chunk from the pool, chained behind, and start again.
      int spare;
      if (!free_.empty()) {
        spare = free_.back();
        free_.pop_back();
      } else {
        spare = static_cast<int>(chunks_.size());
        chunks_.emplace_back();
        chunk = &chunks_[bucket];  // (the array may have moved)
      }
      chunks_[spare] = *chunk;
      chunk->count = 0;
      chunk->next = spare;
    }
    chunk->entry[chunk->count++] = e;
  }

  // One step along the next bucket's chain of chunks (see the top of this file): the chunk
  // reached was prefetched a top() ago. Chunks are never freed to the system (only returned to
  // the pool), so a walk that meets a chunk reused by another bucket reads valid memory and
  // stops at that chain's end: a hint only.
  void walk_next_bucket() {
    if (walker_ == kNone) return;
    const Chunk& chunk = chunks_[walker_];
    for (int k = 0; k < chunk.count; ++k) keys_.prefetch(chunk.entry[k].disc, chunk.entry[k].tag);
    walker_ = chunk.next;
    if (walker_ != kNone) prefetch_line(&chunks_[walker_]);
  }

  // The bucket after the current one is the next to be drained: start loading its first chunk,
  // and walk its chain from the next top() on.
  void start_walk() {
    walker_ = static_cast<int>((current_ + 1) & (buckets_ - 1));
    prefetch_line(&chunks_[walker_]);
  }

  // Appends the first `count` pending entries to their buckets.
  void append_pending(int count) {
    for (int k = 0; k < count; ++k) append(pending_bucket_[k], pending_entry_[k]);
    std::copy(pending_bucket_ + count, pending_bucket_ + pending_, pending_bucket_);
    std::copy(pending_entry_ + count, pending_entry_ + pending_, pending_entry_);
    pending_ -= count;
    waiting_ = std::max(waiting_ - count, 0);
  }

  // The heap ran empty: move the next non-empty bucket into it, or re-plan the calendar.
  void refill() {
    std::int64_t turn = 0;
    while (heap_size_ == 0) {
      if (++turn > buckets_) {  // a whole turn of empty buckets: only the overflow is left
        rebuild(collect());  // (files the earliest entry into the heap, if there is any)
        return;
      }
      ++current_;
      horizon_ = origin_ + static_cast<double>(current_ + 1) * width_;
      const int b = static_cast<int>(current_ & (buckets_ - 1));
      if (b == 0) {
        // A new turn of the calendar. If the last turn saw far more or fewer entries per bucket
        // than planned, the width no longer suits the event rate: re-plan. Otherwise overflow
        // entries that now fall within reach move to their buckets (superseded ones are dropped).
        const double per_bucket = static_cast<double>(moved_) / buckets_;
        moved_ = 0;
        if (per_bucket > 8 * kPerBucket || per_bucket < kPerBucket / 8) {
          rebuild(collect());
          return;
        }
        std::size_t kept = 0;
        for (std::size_t k = 0; k < overflow_.size(); ++k) {
          const Entry e = overflow_[k];
          if (keys_.key(e.disc) != e.time) continue;
          if (bucket_of(e.time) < current_ + buckets_) {
            file(e);  // (never back into overflow_, never a rebuild)
          } else {
            overflow_[kept++] = e;
          }
        }
        overflow_.resize(kept);
      }
      append_pending(pending_);  // (some may belong to this bucket)
      // This bucket is the one being walked (set up by the refill or rebuild before). The entries
      // of the chunks the walk reached have had their data prefetched; entries filed since were
      // just computed by the caller, their data still in its cache. The rest (the chunks from
      // where the walk stopped on) are prefetched now.
      const int unwalked = walker_;
      start_walk();
      bool fetch = false;
      for (int c = b; c >= 0;) {
        Chunk& chunk = chunks_[c];
        fetch = fetch || c == unwalked;
        for (int k = 0; k < chunk.count; ++k) {
          if (fetch) keys_.prefetch(chunk.entry[k].disc, chunk.entry[k].tag);
          heap_push(chunk.entry[k]);
        }
        moved_ += chunk.count;
        const int after = chunk.next;
        chunk.count = 0;
        chunk.next = kNone;
        if (c != b) free_.push_back(c);
        c = after;
      }
    }
  }

  // Every current entry (one or more per disc), the queue emptied.
  std::vector<Entry> collect() {
    append_pending(pending_);
    std::vector<Entry> entries;
    entries.reserve(static_cast<std::size_t>(size_));
    auto keep = [&](const Entry& e) {
      if (keys_.key(e.disc) == e.time) entries.push_back(e);
    };
    for (int k = 0; k < heap_size_; ++k) keep(at(k));
    for (int b = 0; b < buckets_; ++b) {
      for (int c = b; c >= 0; c = chunks_[c].next) {
        for (int k = 0; k < chunks_[c].count; ++k) keep(chunks_[c].entry[k]);
      }
    }
    for (const Entry& e : overflow_) keep(e);
    return entries;
  }

  // Plans the calendar from the entries' times: width from the spread of the finite times,
  // origin at the earliest, then files every entry.
  void rebuild(const std::vector<Entry>& entries) {
    double first = std::numeric_limits<double>::infinity();
    for (const Entry& e : entries) first = std::min(first, e.time);
    double sum = 0.0;
    int finite = 0;
    for (const Entry& e : entries) {
      if (std::isfinite(e.time)) {
        sum += e.time - first;
        ++finite;
      }
    }
    const double spread = finite > 0 ? sum / finite : 0.0;  // mean key distance ahead
    width_ = spread > 0 ? 2 * spread * kPerBucket / std::max(finite, 1) : 1.0;
    // A bucket must be wider than the rounding of its times (keys near 1e20 with a width of 1
    // would all share one horizon, 1e20 + 1 == 1e20): at least 2^-40 of the earliest time.
    if (std::isfinite(first)) width_ = std::max(width_, std::abs(first) * 0x1p-40);
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
    pending_ = waiting_ = 0;
    storage_.assign(std::max(entries.size(), std::size_t{64}) + kPad, Entry{0.0, -1, 0});
    heap_size_ = 0;
    chunks_.assign(static_cast<std::size_t>(buckets_), Chunk{});
    start_walk();
    free_.clear();
    overflow_.clear();
    for (const Entry& e : entries) file(e);
  }

  void heap_push(const Entry& e) {
    if (static_cast<std::size_t>(heap_size_) + kPad >= storage_.size()) storage_.resize(2 * storage_.size());
    sift_up(heap_size_++, e);
  }
  void heap_pop() {
    const int last = --heap_size_;
    if (last > 0) sift_down(0, at(last));
  }

  void sift_up(int k, const Entry& moving) {
    while (k > 0) {
      const int parent = (k - 1) / kArity;
      if (at(parent).time <= moving.time) break;
      at(k) = at(parent);
      k = parent;
    }
    at(k) = moving;
  }
  // Top-down sift of `moving` from slot k; the smallest of four children chosen without branches.
  void sift_down(int k, const Entry moving) {
    const int n = heap_size_;
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
      at(k) = at(child);
      k = child;
    }
    at(k) = moving;
  }

  Keys keys_{};
  int size_ = 0;               // discs
  // The heap of the current bucket (current and superseded entries).
  BigVector<Entry> storage_;   // cache-line aligned
  int heap_size_ = 0;
  // The calendar.
  BigVector<Chunk> chunks_;    // [0, buckets_): each bucket's first chunk; then the pool
  std::vector<int> free_;      // pool chunks not in use
  std::vector<Entry> overflow_;  // entries beyond the calendar's turn
  // Appends waiting for their chunk to arrive: the first waiting_ were made before the last top().
  static constexpr int kPending = 16;
  Entry pending_entry_[kPending];
  int pending_bucket_[kPending];
  int pending_ = 0;
  int waiting_ = 0;
  int walker_ = kNone;         // the next chunk to read on the walk along the next bucket's chain
  int buckets_ = 1;
  double origin_ = 0.0;        // bucket b covers [origin_ + b width_, origin_ + (b + 1) width_)
  double width_ = 1.0;
  double inverse_width_ = 1.0;
  std::int64_t current_ = 0;   // the bucket whose entries are in the heap
  double horizon_ = 0.0;       // end of the current bucket
  std::int64_t moved_ = 0;     // entries moved into the heap during this turn
  int changes_ = 0;            // heap filings past the limit since the last rebuild
};

}  // namespace billiard
