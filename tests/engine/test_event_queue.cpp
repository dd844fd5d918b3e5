// The event queue (lib/src/engine/event_queue.hpp), a calendar of time buckets in front of a small
// heap, against a brute-force minimum: random keys, random changes (earlier, later, far in the
// future, infinite), the pattern of the event loop (pop the top, move it ahead) and a change of
// time scale that forces the calendar to re-plan its bucket width; and how early the queue
// announces the entries it is about to hand out (the prefetch hints of the event loop).
#include "event_queue.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

using Queue = billiard::CalendarQueue<billiard::VectorKeys>;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// n keys drawn uniformly from [0, 10).
std::vector<double> random_keys(int n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<double> keys(n);
  for (double& key : keys) key = 10 * uniform(rng);
  return keys;
}

// The smallest key of a brute-force copy, and whether the queue's top has that key.
void expect_top_is_minimum(Queue& queue, const std::vector<double>& keys) {
  const double least = *std::min_element(keys.begin(), keys.end());
  const Queue::Entry& top = queue.top();
  ASSERT_EQ(top.time, least);
  ASSERT_EQ(keys[top.disc], least);
}

}  // namespace

TEST(EventQueue, RandomChangesKeepTheMinimumOnTop) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const int n = 500;
  std::vector<double> keys = random_keys(n, rng);
  std::vector<int> tags(n);
  std::iota(tags.begin(), tags.end(), 0);
  Queue queue(billiard::VectorKeys{&keys});
  queue.assign(n, tags);
  ASSERT_TRUE(queue.valid());
  double now = 0.0;
  for (int step = 0; step < 200000; ++step) {
    expect_top_is_minimum(queue, keys);
    const Queue::Entry top = queue.top();
    now = top.time;
    ASSERT_EQ(top.tag, tags[top.disc]);
    queue.pop();
    // The top's next event: mostly a little ahead, sometimes far ahead or never.
    const double r = uniform(rng);
    const double next = r < 0.01 ? kInf : r < 0.05 ? now + 1000 * uniform(rng) : now + 10 * uniform(rng);
    keys[top.disc] = next;
    tags[top.disc] = step;
    queue.update(top.disc, next, step);
    // And a random other disc rescheduled (a partner's collision): earlier or later.
    const int other = static_cast<int>(rng() % n);
    keys[other] = now + (uniform(rng) < 0.5 ? 0.01 : 20) * uniform(rng);
    tags[other] = -step;
    queue.update(other, keys[other], tags[other]);
    if (step % 1000 == 0) {
      ASSERT_TRUE(queue.valid()) << "step " << step;
    }
  }
  ASSERT_TRUE(queue.valid());
}

TEST(EventQueue, TimeScaleChangeAndInfiniteKeys) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const int n = 3000;  // more than the heap limit (1024), so that the bucket width is re-planned
  std::vector<double> keys(n, kInf);  // nothing scheduled at first
  Queue queue(billiard::VectorKeys{&keys});
  queue.assign(n);
  ASSERT_TRUE(queue.valid());
  expect_top_is_minimum(queue, keys);
  // Events 1e6 times closer together than before, then 1e6 times further apart.
  double now = 0.0;
  for (double scale : {1.0, 1e-6, 1.0}) {
    for (int d = 0; d < n; ++d) {
      keys[d] = now + scale * uniform(rng);
      queue.update(d, keys[d]);
    }
    for (int step = 0; step < 50000; ++step) {
      expect_top_is_minimum(queue, keys);
      const int disc = queue.top().disc;
      now = queue.top().time;
      queue.pop();
      keys[disc] = now + scale * uniform(rng);
      queue.update(disc, keys[disc]);
    }
    ASSERT_TRUE(queue.valid());
  }
  // Back to nothing scheduled: the top is infinite.
  for (int d = 0; d < n; ++d) {
    keys[d] = kInf;
    queue.update(d, kInf);
  }
  expect_top_is_minimum(queue, keys);
  EXPECT_EQ(queue.top().time, kInf);
  ASSERT_TRUE(queue.valid());
}

TEST(EventQueue, SingleEntryAndEqualKeys) {
  std::vector<double> one = {3.0};
  Queue queue(billiard::VectorKeys{&one});
  queue.assign(1);
  EXPECT_EQ(queue.top().disc, 0);
  queue.pop();
  EXPECT_EQ(queue.upcoming(), nullptr);
  one[0] = 5.0;
  queue.update(0, 5.0);
  EXPECT_EQ(queue.top().time, 5.0);
  // Many equal keys (discs touching at one instant): all come out at that time, each once.
  std::vector<double> keys(50, 2.0);
  Queue equal(billiard::VectorKeys{&keys});
  equal.assign(50);
  std::vector<int> seen(50, 0);
  for (int k = 0; k < 50; ++k) {
    ASSERT_EQ(equal.top().time, 2.0);
    const int disc = equal.top().disc;
    ++seen[disc];
    equal.pop();
    keys[disc] = 4.0 + k;
    equal.update(disc, keys[disc]);
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), 50);
  EXPECT_EQ(equal.top().time, 4.0);
  EXPECT_TRUE(equal.valid());
}

// Superseded entries (the old keys of a disc whose key changed before it came up) never come
// out: a disc moved earlier, later, far away and back again comes out once, at its last key.
TEST(EventQueue, SupersededEntriesNeverComeOut) {
  const int n = 2000;
  std::vector<double> keys(n);
  for (int d = 0; d < n; ++d) keys[d] = 1.0 + d;
  Queue queue(billiard::VectorKeys{&keys});
  queue.assign(n);
  // Disc 7: 8 -> 0.5 (into the current bucket) -> 1500 -> 1e9 (overflow) -> 3.25.
  for (double t : {0.5, 1500.0, 1e9, 3.25}) {
    keys[7] = t;
    queue.update(7, t);
  }
  std::vector<double> popped;
  double last = 0.0;
  for (int k = 0; k < n; ++k) {
    const Queue::Entry top = queue.top();
    ASSERT_EQ(top.time, keys[top.disc]) << "a superseded entry came out at step " << k;
    ASSERT_GE(top.time, last);
    last = top.time;
    if (top.disc == 7) popped.push_back(top.time);
    queue.pop();
    keys[top.disc] = 1e12 + k;  // out of the way
    queue.update(top.disc, keys[top.disc]);
  }
  EXPECT_EQ(popped, std::vector<double>({3.25}));
  EXPECT_TRUE(queue.valid());
}

namespace {

// Keys that remember, for each disc, the number of the top() call during which the queue last
// announced it (Keys::prefetch), so that a test can tell how early entries are announced.
struct AnnouncingKeys {
  const std::vector<double>* keys = nullptr;
  std::vector<long>* announced = nullptr;  // per disc: the top() call of the last announcement
  const long* calls = nullptr;             // top() calls so far
  double key(int disc) const { return (*keys)[static_cast<std::size_t>(disc)]; }
  void prefetch(int disc, int) const { (*announced)[static_cast<std::size_t>(disc)] = *calls; }
};

}  // namespace

// The queue tells the caller which entries are coming (so that their data can be loaded while
// other events are handled). An entry drained from a bucket must be announced during an earlier
// top() call than the one that hands it out: announced only when its bucket is drained, the first
// entry of every bucket would come out in the same call, with no time for its data to arrive
// (measured: 83% early that way, 98.9% with the walk along the next bucket; the rest were filed
// into the next bucket after the walk had passed).
TEST(EventQueue, EntriesAreAnnouncedBeforeTheTopCallThatHandsThemOut) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const int n = 20000;
  std::vector<double> keys = random_keys(n, rng);
  std::vector<long> announced(n, -1);
  long calls = 0;
  billiard::CalendarQueue<AnnouncingKeys> queue(AnnouncingKeys{&keys, &announced, &calls});
  queue.assign(n);
  long early = 0, handed_out = 0;
  for (int step = 0; step < 400000; ++step) {
    ++calls;
    const auto top = queue.top();
    ASSERT_EQ(top.time, keys[top.disc]);
    if (step >= 100000) {  // (after the calendar has settled)
      ++handed_out;
      if (announced[top.disc] >= 0 && announced[top.disc] < calls) ++early;
    }
    queue.pop();
    announced[top.disc] = -1;  // its next entry must be announced again
    keys[top.disc] = top.time + 10 * uniform(rng);
    queue.update(top.disc, keys[top.disc]);
  }
  const double fraction = static_cast<double>(early) / static_cast<double>(handed_out);
  EXPECT_GE(fraction, 0.97) << "only " << fraction << " of the entries handed out by top() were announced "
                            << "during an earlier top() call";
}

// upcoming(changing), called after pop() by the event loop to guess the next event, drops from
// the front of the heap the superseded entries and those of the disc about to be re-keyed (the
// partner of a collision): the tops that follow must be exactly those of a queue that is never
// asked, and the guess must be the next top whenever no earlier key is filed in between.
TEST(EventQueue, UpcomingDropsOnlyEntriesThatCannotComeOut) {
  const int n = 3000;
  std::mt19937_64 rng(11);
  std::vector<double> keys = random_keys(n, rng);
  std::vector<double> plain_keys = keys;
  Queue asked(billiard::VectorKeys{&keys});
  Queue plain(billiard::VectorKeys{&plain_keys});
  asked.assign(n);
  plain.assign(n);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::uniform_int_distribution<int> any_disc(0, n - 1);
  int guesses = 0, right = 0;
  int guessed = -1;
  double now = 0.0;
  for (int step = 0; step < 100000; ++step) {
    const Queue::Entry top = asked.top();
    const Queue::Entry expected = plain.top();
    ASSERT_EQ(top.disc, expected.disc) << "step " << step;
    ASSERT_EQ(top.time, expected.time) << "step " << step;
    if (guessed >= 0) {
      ++guesses;
      right += top.disc == guessed ? 1 : 0;
    }
    now = top.time;
    asked.pop();
    plain.pop();
    // Half the steps are "collisions" with another disc, whose key changes too.
    const int partner = step % 2 == 0 ? any_disc(rng) : -1;
    const Queue::Entry* next = asked.upcoming(partner == top.disc ? -1 : partner);
    guessed = next != nullptr ? next->disc : -1;
    // The popped disc moves ahead (sometimes far); the partner gets a new key after `now`.
    auto rekey = [&](int d, double key) {
      keys[d] = plain_keys[d] = key;
      asked.update(d, key);
      plain.update(d, key);
    };
    rekey(top.disc, now + (step % 50 == 0 ? 1e3 : 2 * uniform(rng)));
    if (partner >= 0 && partner != top.disc) rekey(partner, now + 2 * uniform(rng));
  }
  EXPECT_TRUE(asked.valid());
  // Keys filed earlier than the guess (about one in n here) are the only wrong guesses.
  EXPECT_GT(right, 0.95 * guesses) << right << " of " << guesses << " guesses were the next top";
}
