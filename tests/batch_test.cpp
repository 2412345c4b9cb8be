// The batch runner's pieces that need no render: the scene cache's budget accounting
// (checked against a model of its least-recently-used rule), the cost-balanced shards, and
// the plan's placeholders and collisions.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <random>
#include <set>

#include "session/batch.h"
#include "session/scene_cache.h"
#include "tests/scratch_dir.h"

#ifndef PRISM_SOURCE_DIR
#define PRISM_SOURCE_DIR "."
#endif
#ifndef PRISM_ASSIMP_GLTF2_DIR
#define PRISM_ASSIMP_GLTF2_DIR "/usr/share/assimp/models/glTF2"
#endif

namespace prism {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kScenes = {PRISM_SOURCE_DIR "/scenes/spheres.gltf",
                                          PRISM_SOURCE_DIR "/scenes/whitted.gltf",
                                          PRISM_SOURCE_DIR "/scenes/furnace.gltf"};

SceneRequest request(const std::string& path) {
  SceneRequest r;
  r.path = path;
  return r;
}

SessionOptions one_thread() {
  SessionOptions o;
  o.threads = 1;
  return o;
}

// What each scene's session holds once loaded (no BVH yet: the cache only loads).
std::vector<uint64_t> loaded_sizes() {
  std::vector<uint64_t> sizes;
  for (const std::string& path : kScenes)
    sizes.push_back(Session(request(path), one_thread()).memory_bytes());
  return sizes;
}

// The cache's rule, stated independently: most recently used first; past the budget the least
// recently used session goes, but never the most recently used entry.
struct LruModel {
  uint64_t budget;
  std::vector<uint64_t> sizes;
  std::vector<int> kept;  // scene indices, most recently used first
  int loads = 0, evictions = 0;

  uint64_t bytes() const {
    uint64_t total = 0;
    for (int i : kept) total += sizes[static_cast<size_t>(i)];
    return total;
  }
  void get(int scene) {
    const auto it = std::find(kept.begin(), kept.end(), scene);
    if (it != kept.end()) {
      kept.erase(it);
      kept.insert(kept.begin(), scene);
      return;
    }
    ++loads;
    kept.insert(kept.begin(), scene);
    while (bytes() > budget && kept.size() > 1) {
      kept.pop_back();
      ++evictions;
    }
  }
};

// A fixed, scene-revisiting sequence of gets: every scene, then 40 picks.
std::vector<int> access_sequence() {
  std::vector<int> sequence = {0, 1, 2};
  std::mt19937 random(7);
  for (int i = 0; i < 40; ++i) sequence.push_back(static_cast<int>(random() % kScenes.size()));
  return sequence;
}

// Runs `sequence` on a cache of `budget` and on the model, comparing after every get.
void check_against_model(uint64_t budget, const std::vector<uint64_t>& sizes) {
  SceneCache cache(budget, one_thread());
  LruModel model{budget, sizes, {}, 0, 0};
  for (int scene : access_sequence()) {
    const auto entry = cache.get(request(kScenes[static_cast<size_t>(scene)]));
    model.get(scene);
    ASSERT_TRUE(entry->session) << entry->error;
    EXPECT_EQ(entry->session->memory_bytes(), sizes[static_cast<size_t>(scene)]);
    EXPECT_TRUE(entry->error.empty());
    EXPECT_EQ(cache.loads(), model.loads) << "budget " << budget;
    EXPECT_EQ(cache.evictions(), model.evictions) << "budget " << budget;
    EXPECT_EQ(cache.bytes(), model.bytes()) << "budget " << budget;
    EXPECT_EQ(cache.size(), model.kept.size()) << "budget " << budget;
  }
}

TEST(SceneCache, ScenesWeighSomething) {
  // The budget tests below mean nothing if a scene weighs nothing.
  for (uint64_t size : loaded_sizes()) EXPECT_GT(size, 0u);
}

TEST(SceneCache, BudgetForEverythingLoadsEachSceneOnce) {
  const std::vector<uint64_t> sizes = loaded_sizes();
  const uint64_t all = std::accumulate(sizes.begin(), sizes.end(), uint64_t{0});
  SceneCache cache(all, one_thread());
  std::map<int, std::shared_ptr<const SceneCache::Entry>> first;
  for (int scene : access_sequence()) {
    const auto entry = cache.get(request(kScenes[static_cast<size_t>(scene)]));
    // The very session loaded the first time, not a reload.
    if (!first.count(scene)) first[scene] = entry;
    EXPECT_EQ(entry.get(), first[scene].get());
  }
  EXPECT_EQ(cache.loads(), 3);
  EXPECT_EQ(cache.evictions(), 0);
  EXPECT_EQ(cache.bytes(), all);
  EXPECT_EQ(cache.size(), 3u);
}

TEST(SceneCache, OneByteBudgetKeepsOnlyTheMostRecent) {
  const std::vector<uint64_t> sizes = loaded_sizes();
  SceneCache cache(1, one_thread());
  auto a = cache.get(request(kScenes[0]));
  EXPECT_EQ(cache.bytes(), a->session->memory_bytes());
  auto b = cache.get(request(kScenes[1]));
  EXPECT_EQ(cache.bytes(), b->session->memory_bytes());
  EXPECT_EQ(cache.bytes(), sizes[1]);
  EXPECT_EQ(cache.size(), 1u);
  EXPECT_EQ(cache.evictions(), 1);
  // Going back to the first scene loads it again, and drops the second.
  auto again = cache.get(request(kScenes[0]));
  EXPECT_NE(again.get(), a.get());
  EXPECT_EQ(cache.loads(), 3);
  EXPECT_EQ(cache.evictions(), 2);
  EXPECT_EQ(cache.bytes(), sizes[0]);
  // The same scene twice in a row is kept.
  cache.get(request(kScenes[0]));
  EXPECT_EQ(cache.loads(), 3);
}

TEST(SceneCache, BytesFollowTheLeastRecentlyUsedRuleForEveryBudget) {
  const std::vector<uint64_t> sizes = loaded_sizes();
  const uint64_t all = std::accumulate(sizes.begin(), sizes.end(), uint64_t{0});
  const uint64_t largest = *std::max_element(sizes.begin(), sizes.end());
  const uint64_t smallest = *std::min_element(sizes.begin(), sizes.end());
  // Exactly at and one byte short of each fit, where an off-by-one would show.
  for (uint64_t budget :
       {uint64_t{1}, smallest, largest, largest + smallest, largest + smallest - 1,
        sizes[0] + sizes[1], sizes[1] + sizes[2], sizes[0] + sizes[2], all - 1, all}) {
    SCOPED_TRACE(budget);
    check_against_model(budget, sizes);
  }
}

TEST(SceneCache, RemembersAFailedLoad) {
  const fs::path dir = test::scratch_dir("batch_test_failed_load");
  const std::string garbage = (dir / "garbage.gltf").string();
  std::ofstream(garbage) << "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [";
  for (const std::string& path : {garbage, (dir / "missing.gltf").string()}) {
    SCOPED_TRACE(path);
    SceneCache cache(1, one_thread());
    const auto failed = cache.get(request(path));
    EXPECT_FALSE(failed->session);
    EXPECT_FALSE(failed->error.empty());
    // Other scenes between the failures do not make it load again, even with a tiny budget.
    cache.get(request(kScenes[0]));
    for (int i = 0; i < 3; ++i) {
      const auto again = cache.get(request(path));
      EXPECT_EQ(again.get(), failed.get());
      EXPECT_EQ(again->error, failed->error);
    }
    EXPECT_EQ(cache.loads(), 2);
    // A failure weighs nothing, so the scene is what is held.
    EXPECT_EQ(cache.bytes(), cache.get(request(kScenes[0]))->session->memory_bytes());
  }
  fs::remove_all(dir);
}

// ---- Batch::plan and Batch::shard

class BatchPlan : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("prism_batch_test_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  BatchJobSpec spec(const std::string& name, const std::string& output,
                    const std::string& scene = kScenes[0]) const {
    BatchJobSpec s;
    s.file_index = next_index_++;
    s.name = name;
    s.scene = request(scene);
    s.render.width = 16;
    s.render.height = 9;
    s.render.film.spp = 1;
    s.outputs.exr = (dir_ / output).string();
    return s;
  }
  static BatchOptions options() {
    BatchOptions o;
    o.threads = 1;
    return o;
  }

  fs::path dir_;
  mutable int next_index_ = 0;
};

TEST_F(BatchPlan, SubstitutesEveryPlaceholder) {
  BatchJobSpec a = spec("my job/x", "{scene}-{camera}-{integrator}-{spp}-{job}.exr");
  a.render.integrator = "shadow";
  a.render.film.spp = 7;
  a.outputs.preview = (dir_ / "{job}.png").string();
  a.outputs.sample_counts = (dir_ / "{scene}-counts.exr").string();
  BatchJobSpec b = spec("b", "{scene}-{camera}.exr", kScenes[1]);
  b.render.camera = "main";
  Batch batch({a, b}, options());
  const std::vector<BatchJob>& jobs = batch.plan();
  ASSERT_EQ(jobs.size(), 2u);
  // The job's slash becomes '_': a name cannot reach another folder.
  EXPECT_EQ(jobs[0].files.image, (dir_ / "spheres-default-shadow-7-my_job_x.exr").string());
  EXPECT_EQ(jobs[0].files.preview, (dir_ / "my_job_x.png").string());
  EXPECT_EQ(jobs[0].files.sample_counts, (dir_ / "spheres-counts.exr").string());
  EXPECT_EQ(jobs[0].camera_label, "default");
  EXPECT_EQ(jobs[1].files.image, (dir_ / "whitted-main.exr").string());
  EXPECT_EQ(jobs[1].camera_label, "main");
  EXPECT_EQ(jobs[0].index, 0);
  EXPECT_EQ(jobs[1].index, 1);
  for (const BatchJob& job : jobs) EXPECT_EQ(job.error, "") << job.label();
}

TEST_F(BatchPlan, EveryCameraExpandsIntoOneRenderPerCamera) {
  const std::string cameras = PRISM_ASSIMP_GLTF2_DIR "/cameras/Cameras.gltf";
  if (!fs::exists(cameras)) GTEST_SKIP() << cameras << " is not installed (assimp-testmodels)";
  BatchJobSpec a = spec("all", "{camera}.exr", cameras);
  a.every_camera = true;
  Batch batch({a}, options());
  const std::vector<BatchJob>& jobs = batch.plan();
  ASSERT_EQ(jobs.size(), 2u);
  EXPECT_EQ(jobs[0].spec.render.camera, "0");
  EXPECT_EQ(jobs[1].spec.render.camera, "1");
  EXPECT_EQ(jobs[0].files.image, (dir_ / "cameras_0_.exr").string());
  EXPECT_EQ(jobs[1].files.image, (dir_ / "cameras_1_.exr").string());
  EXPECT_EQ(jobs[1].label(), "jobs[0] 'all' (camera cameras_1_)");

  BatchJobSpec same = spec("same", "one.exr", cameras);
  same.every_camera = true;
  Batch colliding({same}, options());
  try {
    colliding.plan();
    FAIL() << "two cameras into one.exr planned";
  } catch (const BatchError& e) {
    EXPECT_NE(std::string(e.what()).find("jobs[1] 'same' (camera cameras_1_) and jobs[1] 'same' "
                                         "(camera cameras_0_) would both write"),
              std::string::npos)
        << e.what();
  }
}

// The BatchError message of planning `specs`, or "" when it plans.
std::string plan_error(std::vector<BatchJobSpec> specs) {
  // Numbered as a file of just these jobs.
  for (size_t i = 0; i < specs.size(); ++i) specs[i].file_index = static_cast<int>(i);
  BatchOptions o;
  o.threads = 1;
  Batch batch(std::move(specs), o);
  try {
    batch.plan();
  } catch (const BatchError& e) {
    return e.what();
  }
  return "";
}

TEST_F(BatchPlan, CollisionsNameBothJobs) {
  // The same file spelt two ways.
  std::string error = plan_error({spec("a", "out.exr"), spec("b", "./sub/../out.exr")});
  EXPECT_NE(error.find("jobs[1] 'b' and jobs[0] 'a' would both write"), std::string::npos) << error;
  // One job's sample-count image is another's image.
  BatchJobSpec c = spec("c", "c.exr");
  c.outputs.sample_counts = (dir_ / "d.exr").string();
  error = plan_error({c, spec("d", "d.exr")});
  EXPECT_NE(error.find("jobs[1] 'd' and jobs[0] 'c' would both write"), std::string::npos) << error;
  // Placeholders that come out the same.
  error = plan_error({spec("e", "{scene}.exr"), spec("f", "{scene}.exr")});
  EXPECT_NE(
      error.find("jobs[1] 'f' and jobs[0] 'e' would both write " + (dir_ / "spheres.exr").string()),
      std::string::npos)
      << error;
  // Told apart by {job}: no error.
  EXPECT_EQ(plan_error({spec("e", "{job}.exr"), spec("f", "{job}.exr")}), "");
}

TEST_F(BatchPlan, UnknownPlaceholdersAreErrors) {
  std::string error = plan_error({spec("a", "{foo}.exr")});
  EXPECT_NE(error.find("jobs[0] 'a'"), std::string::npos) << error;
  EXPECT_NE(error.find("no placeholder {foo}"), std::string::npos) << error;
  error = plan_error({spec("a", "{scene.exr")});
  EXPECT_NE(error.find("'{' without a closing '}'"), std::string::npos) << error;
  BatchJobSpec p = spec("p", "p.exr");
  p.outputs.preview = (dir_ / "{Scene}.png").string();
  error = plan_error({p});
  EXPECT_NE(error.find("no placeholder {Scene}"), std::string::npos) << error;
}

TEST_F(BatchPlan, ShardsAreDisjointCompleteDeterministicAndBalanced) {
  std::mt19937 random(11);
  std::vector<BatchJobSpec> specs;
  std::vector<double> costs;
  for (int i = 0; i < 37; ++i) {
    BatchJobSpec s = spec("j" + std::to_string(i), "{job}.exr");
    s.render.integrator = "phong";  // cost 1 per sample
    s.render.width = 1 + static_cast<int>(random() % 64);
    s.render.height = 1 + static_cast<int>(random() % 16);
    // A few far costlier than the rest, as a real file has.
    s.render.film.spp = (i % 9 == 0) ? 512 : 1 + static_cast<int>(random() % 32);
    costs.push_back(static_cast<double>(s.render.width) * s.render.height * s.render.film.spp);
    specs.push_back(s);
  }
  Batch batch(specs, options());
  const std::vector<BatchJob>& jobs = batch.plan();
  ASSERT_EQ(jobs.size(), specs.size());
  for (size_t i = 0; i < jobs.size(); ++i) EXPECT_DOUBLE_EQ(jobs[i].cost, costs[i]);
  const double total = std::accumulate(costs.begin(), costs.end(), 0.0);
  const double largest = *std::max_element(costs.begin(), costs.end());

  Batch again(specs, options());
  for (int shards = 1; shards <= 6; ++shards) {
    SCOPED_TRACE(shards);
    std::vector<int> owner(jobs.size(), -1);
    double max_cost = 0.0;
    for (int k = 0; k < shards; ++k) {
      const std::vector<BatchJob> mine = batch.shard(k, shards);
      const std::vector<BatchJob> other = again.shard(k, shards);
      ASSERT_EQ(mine.size(), other.size());
      double cost = 0.0;
      for (size_t i = 0; i < mine.size(); ++i) {
        const size_t index = static_cast<size_t>(mine[i].index);
        EXPECT_EQ(other[i].index, mine[i].index);
        EXPECT_EQ(batch.shard(k, shards)[i].index, mine[i].index);
        if (i > 0) {
          EXPECT_LT(mine[i - 1].index, mine[i].index) << "not in the list's order";
        }
        EXPECT_EQ(owner[index], -1)
            << "job " << index << " in shards " << owner[index] << " and " << k;
        owner[index] = k;
        cost += mine[i].cost;
      }
      max_cost = std::max(max_cost, cost);
    }
    for (size_t i = 0; i < owner.size(); ++i)
      EXPECT_NE(owner[i], -1) << "job " << i << " in no shard";
    // Greedy list scheduling: the last job placed on the fullest shard found it the least
    // loaded, so that shard holds at most the average plus one job.
    EXPECT_LE(max_cost, total / shards + largest);
  }
}

TEST_F(BatchPlan, EqualCostsAlternateFromTheLowerShard) {
  std::vector<BatchJobSpec> specs;
  for (int i = 0; i < 5; ++i) specs.push_back(spec("j" + std::to_string(i), "{job}.exr"));
  Batch batch(specs, options());
  std::vector<int> zero, one;
  for (const BatchJob& j : batch.shard(0, 2)) zero.push_back(j.index);
  for (const BatchJob& j : batch.shard(1, 2)) one.push_back(j.index);
  EXPECT_EQ(zero, (std::vector<int>{0, 2, 4}));
  EXPECT_EQ(one, (std::vector<int>{1, 3}));
  // More shards than jobs: the extra shards are empty, none is lost.
  EXPECT_EQ(batch.shard(5, 7).size(), 0u);
  EXPECT_EQ(batch.shard(4, 7).size(), 1u);
}

}  // namespace
}  // namespace prism
