// Preparations, the one background service of the server's preview and GI bases: what a request
// sees while a value is queued, under way, ready or failed; what is kept; how it stops.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>

#include "core/error.h"
#include "server/preparations.h"

namespace matlas::server {
namespace {

/// Holds each preparation until released, after reporting "half way"; counts calls per key.
class Gate {
public:
  std::shared_ptr<const std::string> prepare(const std::string& key, ProgressSink& progress) {
    {
      std::lock_guard lock(mutex_);
      ++calls_[key];
    }
    progress.update("working on " + key, 1, 2);
    std::unique_lock lock(mutex_);
    opened_.wait(lock, [&] { return open_ || fail_.contains(key); });
    if (fail_.contains(key)) throw Error("no " + key);
    return std::make_shared<const std::string>("value of " + key);
  }
  void open() {
    {
      std::lock_guard lock(mutex_);
      open_ = true;
    }
    opened_.notify_all();
  }
  void fail(const std::string& key) {
    {
      std::lock_guard lock(mutex_);
      fail_.insert(key);
    }
    opened_.notify_all();
  }
  int calls(const std::string& key) {
    std::lock_guard lock(mutex_);
    return calls_[key];
  }

private:
  std::mutex mutex_;
  std::condition_variable opened_;
  bool open_ = false;
  std::set<std::string> fail_;
  std::map<std::string, int> calls_;
};

/// Polls until `done` holds (at most 10 s).
template <class F>
bool eventually(F done) {
  for (int i = 0; i < 1000; ++i) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return done();
}

using Strings = Preparations<std::string>;

Strings::Prepare through(Gate& gate) {
  return [&gate](const std::string& key, ProgressSink& progress) { return gate.prepare(key, progress); };
}

TEST(Preparations, ARequestQueuesTheValueAndSeesItsProgressThenTheValue) {
  Gate gate;
  Strings values(through(gate), 4);
  Strings::Status first = values.request("a");
  EXPECT_EQ(first.value, nullptr);
  EXPECT_TRUE(first.error.empty());
  ASSERT_TRUE(eventually([&] { return values.request("a").progress == 0.5; }));
  const Strings::Status under_way = values.request("a");
  EXPECT_EQ(under_way.stage, "working on a");
  EXPECT_EQ(under_way.value, nullptr);
  // A second key waits behind the first.
  EXPECT_EQ(values.request("b").stage, "waiting for another scene");
  gate.open();
  const Strings::Status ready = values.wait("a");
  ASSERT_NE(ready.value, nullptr);
  EXPECT_EQ(*ready.value, "value of a");
  EXPECT_EQ(ready.progress, 1.0);
  EXPECT_EQ(*values.wait("b").value, "value of b");
  // Asked again and again, each was prepared once.
  for (int i = 0; i < 3; ++i) values.request("a");
  EXPECT_EQ(gate.calls("a"), 1);
  EXPECT_EQ(gate.calls("b"), 1);
}

TEST(Preparations, AFailureIsKeptAndNotPreparedAgain) {
  Gate gate;
  Strings values(through(gate), 4);
  gate.fail("bad");
  const Strings::Status failed = values.wait("bad");
  EXPECT_EQ(failed.value, nullptr);
  EXPECT_EQ(failed.error, "no bad");
  EXPECT_EQ(values.request("bad").error, "no bad");
  EXPECT_EQ(values.request("bad").stage, "failed");
  EXPECT_EQ(gate.calls("bad"), 1);
}

TEST(Preparations, KeepsTheMostRecentlyUsedAndThePinnedAndPreparesADroppedValueAgain) {
  Gate gate;
  gate.open();
  Strings values(through(gate), 1);
  values.pin("default");
  values.put("default", std::make_shared<const std::string>("given"));
  EXPECT_EQ(*values.wait("a").value, "value of a");
  EXPECT_EQ(*values.wait("b").value, "value of b");  // drops a (capacity 1), never the pinned one
  EXPECT_EQ(values.find("a"), nullptr);
  ASSERT_NE(values.find("default"), nullptr);
  EXPECT_EQ(*values.find("default"), "given");
  EXPECT_EQ(gate.calls("default"), 0);
  EXPECT_EQ(*values.wait("a").value, "value of a");
  EXPECT_EQ(gate.calls("a"), 2);
}

TEST(Preparations, DestroyingItCancelsThePreparationUnderWay) {
  std::atomic<bool> started{false}, cancelled{false};
  {
    Strings values(
        [&](const std::string&, ProgressSink& progress) -> std::shared_ptr<const std::string> {
          started = true;
          try {
            for (;;) {
              progress.update("endless", 0, 1);  // throws Cancelled once the owner stops
              std::this_thread::sleep_for(std::chrono::milliseconds(1));
            }
          } catch (const Cancelled&) {
            cancelled = true;
            throw;
          }
        },
        2);
    values.request("forever");
    ASSERT_TRUE(eventually([&] { return started.load(); }));
  }  // returns: the worker stopped
  EXPECT_TRUE(cancelled);
}

}  // namespace
}  // namespace matlas::server
