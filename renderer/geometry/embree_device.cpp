#include "renderer/geometry/embree_device.h"

#include <algorithm>
#include <stdexcept>

namespace prism {

EmbreeDevice::EmbreeDevice(const char* config) : device_(rtcNewDevice(config)) {
  if (!device_) throw std::runtime_error("cannot create the Embree device");
  rtcSetDeviceErrorFunction(device_, report, this);
  rtcSetDeviceMemoryMonitorFunction(device_, monitor, this);
}

bool EmbreeDevice::monitor(void* device, ssize_t bytes, bool) {
  static_cast<EmbreeDevice*>(device)->bytes_.fetch_add(bytes, std::memory_order_relaxed);
  return true;  // never refuse: the session's memory budget is checked before builds
}

EmbreeDevice::~EmbreeDevice() {
  rtcReleaseDevice(device_);
}

void EmbreeDevice::report(void* device, RTCError code, const char* message) {
  if (code == RTC_ERROR_NONE) return;
  auto* self = static_cast<EmbreeDevice*>(device);
  const std::lock_guard<std::mutex> lock(self->mutex_);
  for (ErrorWatch* watch : self->watches_)
    if (watch->first_.empty()) watch->first_ = message ? message : "unknown Embree error";
}

EmbreeDevice::ErrorWatch::ErrorWatch(EmbreeDevice& device) : device_(device) {
  const std::lock_guard<std::mutex> lock(device_.mutex_);
  device_.watches_.push_back(this);
}

EmbreeDevice::ErrorWatch::~ErrorWatch() {
  const std::lock_guard<std::mutex> lock(device_.mutex_);
  auto& watches = device_.watches_;
  watches.erase(std::find(watches.begin(), watches.end(), this));
}

std::string EmbreeDevice::ErrorWatch::first_error() const {
  const std::lock_guard<std::mutex> lock(device_.mutex_);
  return first_;
}

void EmbreeDevice::ErrorWatch::throw_if_failed() const {
  const std::string error = first_error();
  if (!error.empty()) throw std::runtime_error("Embree: " + error);
}

}  // namespace prism
