#include "server/serving.h"

#include <csignal>
#include <cstdlib>
#include <pthread.h>

namespace matlas::server {

std::filesystem::path default_cache_dir() {
  if (const char* c = std::getenv("MATLAS_CACHE"); c && *c) return c;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::filesystem::path(x) / "matlas";
  if (const char* h = std::getenv("HOME"); h && *h) return std::filesystem::path(h) / ".cache" / "matlas";
  return std::filesystem::temp_directory_path() / "matlas-cache";
}

namespace {
sigset_t stop_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}
}  // namespace

void block_stop_signals() {
  const sigset_t set = stop_signals();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
}

void wait_for_stop_signal() {
  const sigset_t set = stop_signals();
  int sig = 0;
  sigwait(&set, &sig);
}

}  // namespace matlas::server
