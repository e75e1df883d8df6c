#include "rtc_library.h"

#include <dlfcn.h>

namespace obvh::tools {

// The handle is deliberately never closed: both libraries start TBB worker threads that can outlive
// the release of the last device, and unmapping their code under a running thread crashes at exit.
RtcLibrary::~RtcLibrary() = default;

std::unique_ptr<RtcLibrary> RtcLibrary::open(const std::string& path, const std::string& label, std::string& error) {
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND);
  if (!handle) {
    const char* why = dlerror();
    error = "cannot load " + path + ": " + (why ? why : "unknown error");
    return nullptr;
  }
  auto lib = std::make_unique<RtcLibrary>();
  lib->handle_ = handle;
  lib->path = path;
  lib->label = label;
#define OBVH_LOAD_POINTER(name)                                                        \
  lib->name = reinterpret_cast<decltype(&::name)>(dlsym(handle, #name));               \
  if (!lib->name) {                                                                    \
    error = path + " does not export " #name;                                         \
    return nullptr;                                                                    \
  }
  OBVH_RTC_FUNCTIONS(OBVH_LOAD_POINTER)
#undef OBVH_LOAD_POINTER
  lib->obvhEnableTraversalStatistics =
      reinterpret_cast<decltype(&::obvhEnableTraversalStatistics)>(dlsym(handle, "obvhEnableTraversalStatistics"));
  lib->obvhTakeTraversalStatistics =
      reinterpret_cast<decltype(&::obvhTakeTraversalStatistics)>(dlsym(handle, "obvhTakeTraversalStatistics"));
  if (!lib->obvhEnableTraversalStatistics || !lib->obvhTakeTraversalStatistics)
    lib->obvhEnableTraversalStatistics = nullptr, lib->obvhTakeTraversalStatistics = nullptr;
  return lib;
}

std::string referenceEmbreePath() { return OBVH_REFERENCE_EMBREE_PATH; }
std::string obvhDropInPath() { return OBVH_DROPIN_PATH; }

}  // namespace obvh::tools
