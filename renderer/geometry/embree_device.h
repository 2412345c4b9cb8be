// One Embree device for every scene a process (or a session) builds: a device starts its own
// thread pool and allocators, which scenes built one after another can share. Scenes keep
// the device alive through their std::shared_ptr, so it is released after the last of them.
#pragma once

#include <atomic>
#include <mutex>
#include <string>
#include <vector>

#include <embree3/rtcore.h>

namespace prism {

class EmbreeDevice {
 public:
  // `config` is rtcNewDevice's configuration string (null: Embree's defaults). Throws
  // std::runtime_error if Embree cannot make the device.
  explicit EmbreeDevice(const char* config = nullptr);
  ~EmbreeDevice();
  EmbreeDevice(const EmbreeDevice&) = delete;
  EmbreeDevice& operator=(const EmbreeDevice&) = delete;

  RTCDevice get() const { return device_; }

  // Bytes Embree holds on this device now (its memory monitor): BVHs and their build
  // buffers, not the geometry buffers Prism shares with it.
  long long bytes_in_use() const { return bytes_.load(std::memory_order_relaxed); }

  // Collects the first error Embree reports on the device while it lives, from any thread
  // (Embree reports from the threads of a parallel build). Embree errors carry no scene, so
  // while several builds on one device overlap, each one's watch sees every error: a failed
  // build is never missed, though another build running beside it fails too.
  class ErrorWatch {
   public:
    explicit ErrorWatch(EmbreeDevice& device);
    ~ErrorWatch();
    ErrorWatch(const ErrorWatch&) = delete;
    ErrorWatch& operator=(const ErrorWatch&) = delete;
    // Empty while Embree has reported nothing.
    std::string first_error() const;
    // Throws std::runtime_error("Embree: <message>") if Embree has reported an error.
    void throw_if_failed() const;

   private:
    friend class EmbreeDevice;
    EmbreeDevice& device_;
    std::string first_;  // guarded by device_.mutex_
  };

 private:
  static void report(void* device, RTCError code, const char* message);
  static bool monitor(void* device, ssize_t bytes, bool post);

  RTCDevice device_ = nullptr;
  std::atomic<long long> bytes_{0};
  mutable std::mutex mutex_;
  std::vector<ErrorWatch*> watches_;
};

}  // namespace prism
