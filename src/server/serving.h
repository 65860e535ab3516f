#pragma once
// What the serving commands (`matlas serve`, `matlas demo`) share: the cache folder, and running
// a server until the process is interrupted.
#include <filesystem>

namespace matlas::server {

class AtlasServer;

/// The cache folder of models and image bases: $MATLAS_CACHE, else $XDG_CACHE_HOME/matlas, else
/// ~/.cache/matlas, else <temp>/matlas-cache. Not created here.
std::filesystem::path default_cache_dir();

/// Starts the server, calls on_ready(url) once it listens, and serves until SIGINT or SIGTERM;
/// then stops it cleanly. The signals are blocked in every thread the server starts.
template <class F>
void serve_until_signal(AtlasServer& server, F&& on_ready);

/// Non-template part of serve_until_signal: blocks SIGINT/SIGTERM in this thread (inherited by
/// the threads started after it) and waits for one of them.
void block_stop_signals();
void wait_for_stop_signal();

}  // namespace matlas::server

#include "server/atlas_server.h"

namespace matlas::server {

template <class F>
void serve_until_signal(AtlasServer& server, F&& on_ready) {
  block_stop_signals();
  server.start();
  on_ready(server.url());
  wait_for_stop_signal();
  server.stop();
}

}  // namespace matlas::server
