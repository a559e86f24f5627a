#pragma once
/// \file
/// The live view's server (docs/viewer.md "Live view"): one page over HTTP and a
/// WebSocket at /ws, on 127.0.0.1 only, served by Boost.Beast (Debian's
/// libboost-dev, header-only) on a thread of its own. It knows nothing of the
/// physics: it sends what it is given (frames as binary messages, status as
/// text) and hands over the text messages viewers send. Optional, like MPI:
/// built when Boost.Beast is found (liveServerAvailable()).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace robophi::output {

/// Whether this build has the live view's server (Boost.Beast was found).
bool liveServerAvailable();

/// The server. Its thread runs until the destructor. Each viewer's first message
/// is the text {"type":"hello"}: from then on it counts in viewers().
class LiveServer {
 public:
  /// Serves `page` (HTML) at / and a WebSocket at /ws on 127.0.0.1:`port` (0: a
  /// free port the system picks). Throws std::runtime_error when the port cannot
  /// be bound (naming it and why) or the server is not built.
  LiveServer(std::string page, int port);
  ~LiveServer();
  LiveServer(const LiveServer&) = delete;
  LiveServer& operator=(const LiveServer&) = delete;

  /// The port bound.
  int port() const;
  /// "http://127.0.0.1:PORT/".
  std::string url() const;
  /// Sends a binary message (a frame) to every viewer; a viewer still busy with
  /// the previous frame gets only the latest (frames are never queued up).
  void sendFrame(std::string bytes);
  /// Sends a text message to every viewer, after those sent before it.
  void sendText(std::string text);
  /// The text messages viewers sent since the last call, in order.
  std::vector<std::string> takeMessages();
  /// Viewers connected now (open WebSockets).
  int viewers() const;
  /// WebSockets opened since the start.
  std::int64_t connections() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace robophi::output
