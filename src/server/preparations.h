#pragma once
// Preparations: values prepared in the background by one worker thread, one at a time, in the
// order first asked for, with their progress while under way: the one background service behind
// the server's preview bases (BasisPreviews: a scene's image basis) and GI bases (GiScenes: a
// scene's GI basis). A request for a value not prepared yet queues it and answers how far it got;
// a failure is kept and answered to every later request; prepared values are kept in an LruCache
// (pinned keys never dropped; a dropped value is prepared again when asked for). Destroying it
// stops the worker: a preparation under way is cancelled through its progress sink (its next
// update throws Cancelled, server/cancellable_sink.h) and waiters wake.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <utility>

#include "core/parallel.h"
#include "core/progress.h"
#include "server/cancellable_sink.h"
#include "server/lru_cache.h"

namespace matlas::server {

template <class Value>
class Preparations {
public:
  /// What a request sees.
  struct Status {
    std::shared_ptr<const Value> value;  ///< null until ready
    double progress = 0;                 ///< [0, 1]
    std::string stage;                   ///< what is being done, for people
    double seconds = 0;                  ///< since its preparation started (0 while queued)
    double seconds_left = -1;            ///< estimated from the rate so far; < 0: not known yet
    std::string error;                   ///< non-empty: the preparation failed
  };
  /// Prepares the value of a key, reporting to `progress` (update: stage and fraction); runs on
  /// the worker thread.
  using Prepare = std::function<std::shared_ptr<const Value>(const std::string& key, ProgressSink& progress)>;

  Preparations(Prepare prepare, std::size_t max_kept) : prepare_(std::move(prepare)), kept_(max_kept) {
    // Background work: requests a user waits for (a refinement, a drag's preview) get the cores
    // and the worker threads first (core/parallel.h).
    worker_ = std::thread([this] { run_in_background([this] { work(); }); });
  }
  ~Preparations() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    changed_.notify_all();
    worker_.join();
  }
  Preparations(const Preparations&) = delete;
  Preparations& operator=(const Preparations&) = delete;

  /// `key` is never dropped once prepared.
  void pin(const std::string& key) {
    std::lock_guard lock(mutex_);
    kept_.pin(key);
  }
  /// A value prepared elsewhere (before serving, or given as a file): ready from now on.
  void put(const std::string& key, std::shared_ptr<const Value> value) {
    {
      std::lock_guard lock(mutex_);
      kept_.put(key, std::move(value));
      failed_.erase(key);
    }
    changed_.notify_all();
  }

  /// The value when ready; else its progress, the key queued unless it failed or is queued.
  Status request(const std::string& key) {
    std::lock_guard lock(mutex_);
    return locked_request(key);
  }
  /// The value when ready, without queueing it (null otherwise).
  std::shared_ptr<const Value> find(const std::string& key) {
    std::lock_guard lock(mutex_);
    const auto* kept = kept_.find(key);
    return kept ? *kept : nullptr;
  }
  /// Queues `key` like request() and blocks until it is ready, failed or the worker stops.
  Status wait(const std::string& key) {
    std::unique_lock lock(mutex_);
    for (;;) {
      Status s = locked_request(key);
      if (s.value || !s.error.empty()) return s;
      if (stop_) {
        s.error = "the server is shutting down";
        return s;
      }
      changed_.wait(lock);
    }
  }
  /// Set while the worker stops: other long work of the owner can stop with it (CancellableSink).
  const std::atomic<bool>& stopping() const { return stop_; }

private:
  /// The preparation under way.
  struct UnderWay {
    std::string key;
    std::string stage = "starting";
    double progress = 0;
    std::chrono::steady_clock::time_point started;
  };

  /// Records the worker's progress in under_way_.
  class Recorder final : public ProgressSink {
  public:
    explicit Recorder(Preparations& owner) : owner_(owner) {}
    void update(const std::string& label, std::uint64_t done, std::uint64_t total) override {
      std::lock_guard lock(owner_.mutex_);
      if (!label.empty()) owner_.under_way_.stage = label;
      owner_.under_way_.progress =
          total ? std::clamp(static_cast<double>(done) / static_cast<double>(total), 0.0, 1.0) : 0.0;
    }
    void message(const std::string&) override {}
    void finish(const std::string&) override {}

  private:
    Preparations& owner_;
  };

  Status locked_request(const std::string& key) {
    Status s;
    if (const auto* kept = kept_.find(key)) {
      s.value = *kept;
      s.progress = 1;
      s.stage = "ready";
      return s;
    }
    if (const auto f = failed_.find(key); f != failed_.end()) {
      s.stage = "failed";
      s.error = f->second;
      return s;
    }
    if (queued_.insert(key).second) {
      queue_.push_back(key);
      changed_.notify_all();
    }
    if (under_way_.key != key) {
      s.stage = under_way_.key.empty() ? "queued" : "waiting for another scene";
      return s;
    }
    s.stage = under_way_.stage;
    s.progress = under_way_.progress;
    s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - under_way_.started).count();
    if (s.progress >= 0.02 && s.seconds >= 1.0) s.seconds_left = s.seconds * (1.0 - s.progress) / s.progress;
    return s;
  }

  void work() {
    for (;;) {
      std::string key;
      {
        std::unique_lock lock(mutex_);
        changed_.wait(lock, [&] { return stop_ || !queue_.empty(); });
        if (stop_) return;
        key = queue_.front();
        queue_.pop_front();
        under_way_ = UnderWay{key, "starting", 0.0, std::chrono::steady_clock::now()};
      }
      std::shared_ptr<const Value> value;
      std::string error;
      try {
        Recorder recorder(*this);
        CancellableSink sink(recorder, stop_);
        value = prepare_(key, sink);
        if (!value) error = "nothing was prepared";
      } catch (const Cancelled&) {
        return;
      } catch (const std::exception& e) {
        error = e.what();
      }
      {
        std::lock_guard lock(mutex_);
        if (value) kept_.put(key, std::move(value));
        else failed_[key] = error;
        queued_.erase(key);
        under_way_ = UnderWay{};
      }
      changed_.notify_all();
    }
  }

  Prepare prepare_;
  std::mutex mutex_;
  std::condition_variable changed_;
  LruCache<std::shared_ptr<const Value>> kept_;
  std::map<std::string, std::string> failed_;
  std::deque<std::string> queue_;
  std::set<std::string> queued_;
  UnderWay under_way_;
  std::atomic<bool> stop_{false};
  std::thread worker_;  // last: started once everything it uses exists
};

}  // namespace matlas::server
