#include "session/scene_cache.h"

#include <iterator>

#include "session/job_fingerprint.h"

namespace prism {

SceneCache::SceneCache(uint64_t budget_bytes, SessionOptions options)
    : budget_(budget_bytes), options_(std::move(options)) {}

std::string SceneCache::key(const SceneRequest& request) {
  // The settings' scene lines are exactly the load's choices.
  const std::string settings = canonical_settings(request, RenderJob{}, ExrPixelType::float32);
  return settings.substr(0, settings.find("integrator="));
}

std::shared_ptr<const SceneCache::Entry> SceneCache::get(const SceneRequest& request) {
  const std::string wanted = key(request);
  for (auto it = entries_.begin(); it != entries_.end(); ++it) {
    if ((*it)->key != wanted) continue;
    entries_.splice(entries_.begin(), entries_, it);
    return entries_.front();
  }
  auto entry = std::make_shared<Entry>();
  entry->key = wanted;
  ++loads_;
  try {
    entry->session = std::make_shared<Session>(request, options_);
    entry->inputs = hash_inputs(entry->session->scene().source_files);
  } catch (const RequestError& e) {
    entry->session.reset();
    entry->error = e.what();
    entry->request_error = true;
  } catch (const std::exception& e) {
    entry->session.reset();
    entry->error = e.what();
  }
  entries_.push_front(entry);
  trim();
  return entry;
}

uint64_t SceneCache::bytes() const {
  uint64_t total = 0;
  for (const auto& entry : entries_)
    if (entry->session) total += entry->session->memory_bytes();
  return total;
}

void SceneCache::trim() {
  // Failed loads weigh nothing and stay, so a scene's later jobs fail without a reload.
  while (bytes() > budget_) {
    auto victim = entries_.end();
    for (auto it = std::next(entries_.begin()); it != entries_.end(); ++it)
      if ((*it)->session) victim = it;
    if (victim == entries_.end()) return;
    entries_.erase(victim);
    ++evictions_;
  }
}

}  // namespace prism
