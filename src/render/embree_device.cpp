#include "render/embree_device.h"

#include <string>

#include "core/error.h"

namespace matlas::render {

namespace {

void ignore_error(void*, RTCError, const char*) {
  // Failures are reported through the return values (a null handle, a failed commit), which the
  // callers turn into matlas::Error; the default would print to stderr.
}

}  // namespace

RTCDevice embree_device() {
  static const RTCDevice device = [] {
    RTCDevice d = rtcNewDevice(nullptr);
    if (d) rtcSetDeviceErrorFunction(d, ignore_error, nullptr);
    return d;
  }();
  if (!device) throw Error("cannot create the Embree device (" + std::to_string(rtcGetDeviceError(nullptr)) + ")");
  return device;
}

}  // namespace matlas::render
