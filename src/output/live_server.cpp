// The live view's server: Boost.Beast's HTTP and WebSocket over Boost.Asio, on
// one thread of its own (every socket operation runs there; the run's thread
// only posts to it and takes the messages under a mutex).
#include "output/live_server.h"

#include <atomic>
#include <deque>
#include <mutex>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <utility>

#if ROBOPHI_HAVE_LIVE
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#endif

namespace robophi::output {

#if ROBOPHI_HAVE_LIVE

namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

}  // namespace

bool liveServerAvailable() { return true; }

struct LiveServer::Impl {
  // One viewer's WebSocket: reads its messages; writes text in order and frames
  // latest-wins, one write at a time (Beast allows one outstanding write).
  struct Socket : std::enable_shared_from_this<Socket> {
    websocket::stream<beast::tcp_stream> ws;
    Impl* owner;
    beast::flat_buffer readBuffer;
    std::deque<std::shared_ptr<const std::string>> texts;
    std::shared_ptr<const std::string> frame;  // the latest frame not yet sent
    std::shared_ptr<const std::string> writing;
    bool open = false;

    Socket(tcp::socket socket, Impl* o) : ws(std::move(socket)), owner(o) {}

    void accept(http::request<http::string_body> request) {
      ws.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
      ws.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
        if (ec) return;
        self->open = true;
        self->owner->sockets.push_back(self);
        ++self->owner->connectionCount;
        self->owner->viewerCount = static_cast<int>(self->owner->sockets.size());
        // The first message: the viewer is counted from here on.
        self->texts.push_back(std::make_shared<const std::string>(R"({"type":"hello"})"));
        self->read();
        self->write();
      });
    }
    void read() {
      ws.async_read(readBuffer, [self = shared_from_this()](beast::error_code ec, std::size_t) {
        if (ec) {
          self->close();
          return;
        }
        if (self->ws.got_text()) {
          std::lock_guard lock(self->owner->messagesMutex);
          self->owner->messages.push_back(beast::buffers_to_string(self->readBuffer.data()));
        }
        self->readBuffer.consume(self->readBuffer.size());
        self->read();
      });
    }
    void write() {
      if (!open || writing) return;
      bool text = true;
      if (!texts.empty()) {
        writing = texts.front();
        texts.pop_front();
      } else if (frame) {
        writing = std::move(frame);
        frame.reset();
        text = false;
      } else {
        return;
      }
      ws.text(text);
      ws.async_write(net::buffer(*writing),
                     [self = shared_from_this()](beast::error_code ec, std::size_t) {
                       self->writing.reset();
                       if (ec) {
                         self->close();
                         return;
                       }
                       self->write();
                     });
    }
    void close() {
      if (!open) return;
      open = false;
      auto& list = owner->sockets;
      for (auto it = list.begin(); it != list.end(); ++it) {
        if (it->get() == this) {
          list.erase(it);
          break;
        }
      }
      owner->viewerCount = static_cast<int>(list.size());
    }
  };

  // One HTTP connection: a request, then the page (or 404), or the WebSocket's upgrade.
  struct Connection : std::enable_shared_from_this<Connection> {
    beast::tcp_stream stream;
    Impl* owner;
    beast::flat_buffer buffer;
    http::request<http::string_body> request;
    http::response<http::string_body> response;

    Connection(tcp::socket socket, Impl* o) : stream(std::move(socket)), owner(o) {}

    void start() {
      stream.expires_after(std::chrono::seconds(30));
      http::async_read(stream, buffer, request,
                       [self = shared_from_this()](beast::error_code ec, std::size_t) {
                         if (!ec) self->answer();
                       });
    }
    // Only this machine's own pages: the Host must be the server's address (no
    // DNS rebinding), and a browser's WebSocket must come from the served page
    // (another site open in the same browser may not drive the run).
    bool local() const {
      const std::string port = std::to_string(owner->port);
      const auto ours = [&](std::string_view value, std::string_view scheme) {
        for (const char* host : {"127.0.0.1:", "localhost:"}) {
          if (value == std::string(scheme) + host + port) return true;
        }
        return false;
      };
      const auto text = [](beast::string_view v) { return std::string_view(v.data(), v.size()); };
      if (!ours(text(request[http::field::host]), "")) return false;
      const auto origin = request.find(http::field::origin);
      return origin == request.end() || ours(text(origin->value()), "http://");
    }
    void answer() {
      if (!local()) return;  // (dropped)
      if (websocket::is_upgrade(request)) {
        if (request.target() != "/ws") return;  // (dropped: only /ws is a socket)
        stream.expires_never();
        std::make_shared<Socket>(stream.release_socket(), owner)->accept(std::move(request));
        return;
      }
      const bool page = request.method() == http::verb::get &&
                        (request.target() == "/" || request.target() == "/index.html");
      response = http::response<http::string_body>(page ? http::status::ok : http::status::not_found,
                                                   request.version());
      response.set(http::field::server, "robophi");
      response.set(http::field::content_type, page ? "text/html; charset=utf-8" : "text/plain");
      response.set(http::field::cache_control, "no-store");
      response.body() = page ? owner->page : std::string("not found\n");
      response.prepare_payload();
      response.keep_alive(request.keep_alive());
      http::async_write(stream, response,
                        [self = shared_from_this()](beast::error_code ec, std::size_t) {
                          if (ec) return;
                          if (!self->response.keep_alive()) {
                            beast::error_code ignored;
                            self->stream.socket().shutdown(tcp::socket::shutdown_send, ignored);
                            return;
                          }
                          self->request = {};
                          self->start();
                        });
    }
  };

  std::string page;
  net::io_context io;
  tcp::acceptor acceptor{io};
  std::vector<std::shared_ptr<Socket>> sockets;  // (server thread only)
  std::atomic<int> viewerCount{0};
  std::atomic<std::int64_t> connectionCount{0};
  std::mutex messagesMutex;
  std::vector<std::string> messages;
  std::thread thread;
  int port = 0;

  void accept() {
    acceptor.async_accept([this](beast::error_code ec, tcp::socket socket) {
      if (ec) return;  // closed
      std::make_shared<Connection>(std::move(socket), this)->start();
      accept();
    });
  }
};

LiveServer::LiveServer(std::string page, int port) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.page = std::move(page);
  const tcp::endpoint endpoint(net::ip::make_address("127.0.0.1"),
                               static_cast<unsigned short>(port));
  beast::error_code ec;
  s.acceptor.open(endpoint.protocol(), ec);
  if (!ec) s.acceptor.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) s.acceptor.bind(endpoint, ec);
  if (!ec) s.acceptor.listen(net::socket_base::max_listen_connections, ec);
  if (ec)
    throw std::runtime_error("the live view cannot listen on 127.0.0.1:" + std::to_string(port) +
                             " (" + ec.message() + "); choose another --live-port (0: any free one)");
  s.port = s.acceptor.local_endpoint().port();
  s.accept();
  s.thread = std::thread([this] { impl_->io.run(); });
}

LiveServer::~LiveServer() {
  Impl& s = *impl_;
  // Closes every socket on the server's thread, then stops it.
  net::post(s.io, [&s] {
    beast::error_code ignored;
    s.acceptor.close(ignored);
    for (const auto& socket : std::vector(s.sockets)) {
      socket->open = false;
      beast::get_lowest_layer(socket->ws).socket().close(ignored);
    }
    s.sockets.clear();
    s.viewerCount = 0;
  });
  net::post(s.io, [&s] { s.io.stop(); });
  if (s.thread.joinable()) s.thread.join();
}

int LiveServer::port() const { return impl_->port; }

std::string LiveServer::url() const {
  return "http://127.0.0.1:" + std::to_string(impl_->port) + "/";
}

void LiveServer::sendFrame(std::string bytes) {
  auto message = std::make_shared<const std::string>(std::move(bytes));
  net::post(impl_->io, [s = impl_.get(), message] {
    for (const auto& socket : s->sockets) {
      socket->frame = message;
      socket->write();
    }
  });
}

void LiveServer::sendText(std::string text) {
  auto message = std::make_shared<const std::string>(std::move(text));
  net::post(impl_->io, [s = impl_.get(), message] {
    for (const auto& socket : s->sockets) {
      socket->texts.push_back(message);
      socket->write();
    }
  });
}

std::vector<std::string> LiveServer::takeMessages() {
  std::lock_guard lock(impl_->messagesMutex);
  return std::exchange(impl_->messages, {});
}

int LiveServer::viewers() const { return impl_->viewerCount.load(); }

std::int64_t LiveServer::connections() const { return impl_->connectionCount.load(); }

#else  // without Boost.Beast: the live view says it is not built

bool liveServerAvailable() { return false; }

struct LiveServer::Impl {};

LiveServer::LiveServer(std::string page, int port) {
  (void)page;
  (void)port;
  throw std::runtime_error(
      "the live view is not built: it needs Boost.Beast (Debian's libboost-dev; "
      "scripts/install-deps.sh installs it), then rebuild robophi");
}
LiveServer::~LiveServer() = default;
int LiveServer::port() const { return 0; }
std::string LiveServer::url() const { return {}; }
void LiveServer::sendFrame(std::string bytes) { (void)bytes; }
void LiveServer::sendText(std::string text) { (void)text; }
std::vector<std::string> LiveServer::takeMessages() { return {}; }
int LiveServer::viewers() const { return 0; }
std::int64_t LiveServer::connections() const { return 0; }

#endif

}  // namespace robophi::output
