// The scenes a batch keeps loaded: each scene (file and load choices) is loaded once and its
// session, BVH included, reused by every job that names it, while the bytes they hold stay
// within a budget; past it the least recently used is dropped (and loaded again if a later
// job needs it). A scene that fails to load is remembered as failed, so its other jobs fail
// at once with the same message instead of loading it again.
#pragma once

#include <cstdint>
#include <list>
#include <memory>
#include <string>
#include <vector>

#include "session/job_fingerprint.h"
#include "session/session.h"

namespace prism {

class SceneCache {
 public:
  struct Entry {
    std::string key;
    std::shared_ptr<Session> session;  // null when the load failed
    std::string error;                 // why it failed
    bool request_error = false;        // the error was the request's (RequestError "scene")
    std::vector<InputFile> inputs;     // the scene's files with their hashes, at load time
  };

  // `budget_bytes`: what the kept sessions may hold together (Session::memory_bytes); the
  // one most recently used is kept whatever its size. `options` is every session's (its
  // arena is shared by all of them).
  SceneCache(uint64_t budget_bytes, SessionOptions options);

  // The session of `request`, loaded now or kept from before; never throws for a scene that
  // cannot be loaded (Entry::error says why).
  std::shared_ptr<const Entry> get(const SceneRequest& request);
  // Drops sessions, least recently used first, until the rest fit the budget; the most
  // recently used one stays. Called by get, and by the batch after each render (a build
  // makes a session heavier).
  void trim();

  int loads() const { return loads_; }          // scenes loaded so far, reloads included
  int evictions() const { return evictions_; }  // sessions dropped for the budget
  uint64_t bytes() const;                       // what the kept sessions hold now
  size_t size() const { return entries_.size(); }

  // The key two requests share exactly when they load the same thing.
  static std::string key(const SceneRequest& request);

 private:
  uint64_t budget_;
  SessionOptions options_;
  std::list<std::shared_ptr<Entry>> entries_;  // most recently used first
  int loads_ = 0, evictions_ = 0;
};

}  // namespace prism
