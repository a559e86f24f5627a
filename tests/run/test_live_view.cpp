// The live view (src/run/live_view.h) with a WebSocket client of Boost.Beast:
// a watched world steps as an unwatched one (the same state hash), the frames
// carry the state, and a drag's work is the world's external work. Skipped when
// robophi was built without the live view. (The page in a browser:
// tests/viewer/live.test.mjs.)
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <string>
#include <thread>

#include "output/live_server.h"
#include "robophi/scene/scene.h"
#include "robophi/world.h"
#include "run/live_view.h"

#if ROBOPHI_HAVE_LIVE
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#endif

namespace robophi {
namespace {

#if ROBOPHI_HAVE_LIVE

namespace beast = boost::beast;
namespace net = boost::asio;
using tcp = net::ip::tcp;

// A viewer: the WebSocket at /ws of `port`, past the server's hello.
struct Viewer {
  net::io_context io;
  beast::websocket::stream<tcp::socket> ws{io};
  explicit Viewer(int port) {
    tcp::resolver resolver(io);
    net::connect(ws.next_layer(), resolver.resolve("127.0.0.1", std::to_string(port)));
    ws.handshake("127.0.0.1:" + std::to_string(port), "/ws");
    EXPECT_EQ(read(), R"({"type":"hello"})");
  }
  std::string read() {
    beast::flat_buffer buffer;
    ws.read(buffer);
    return beast::buffers_to_string(buffer.data());
  }
  // The next binary message's header (8 doubles) and its particle count.
  std::pair<std::vector<double>, std::size_t> frame() {
    for (;;) {
      const std::string bytes = read();
      if (ws.got_text()) continue;
      std::vector<double> header(8);
      std::memcpy(header.data(), bytes.data(), 8 * sizeof(double));
      return {header, (bytes.size() - 8 * sizeof(double)) / (3 * sizeof(float))};
    }
  }
  void send(const std::string& text) {
    ws.text(true);
    ws.write(net::buffer(text));
  }
};

Scene pendulum() {
  SceneLoadResult loaded = loadSceneFile(std::string(ROBOPHI_SOURCE_DIR) + "/scenes/pendulum.json");
  EXPECT_TRUE(loaded.ok());
  return std::move(*loaded.scene);
}

// As fast as possible, the viewers' messages read after every step.
LiveViewSettings everyStep() {
  LiveViewSettings settings;
  settings.port = 0;
  settings.waitSeconds = 0.0;
  settings.speed = 0.0;
  settings.frameRate = 1e9;
  return settings;
}

TEST(LiveView, AWatchedWorldStepsAsAnUnwatchedOneAndItsFramesCarryTheState) {
  const Scene scene = pendulum();
  World plain(scene.model, scene.initial, scene.run.integrator);
  World watched(scene.model, scene.initial, scene.run.integrator);
  LiveView view(scene, scene.initial, everyStep());
  ASSERT_EQ(view.url().rfind("http://127.0.0.1:", 0), 0u) << view.url();
  Viewer viewer(std::stoi(view.url().substr(17)));
  for (int k = 0; k < 2000; ++k) {
    plain.step(1e-4);
    watched.step(1e-4);
    ASSERT_TRUE(view.afterStep(watched));
  }
  EXPECT_EQ(stateHash(watched.state()), stateHash(plain.state()));
  const auto [header, particles] = viewer.frame();
  EXPECT_EQ(particles, static_cast<std::size_t>(scene.model.particleCount()));
  EXPECT_GT(header[0], 0.0);
  EXPECT_LE(header[0], watched.state().time);
  EXPECT_EQ(header[6], 0.0);   // no drag
  EXPECT_EQ(header[7], -1.0);  // nothing held
}

TEST(LiveView, ADragIsExternalWorkAndPullsTheParticle) {
  const Scene scene = pendulum();
  World world(scene.model, scene.initial, scene.run.integrator);
  LiveView view(scene, scene.initial, everyStep());
  Viewer viewer(std::stoi(view.url().substr(17)));
  world.step(1e-4);
  view.afterStep(world);
  viewer.frame();  // (counted as a viewer by now)
  // The bob (particle 3, at rest at (1, 0, 1.5)) pulled towards a point above the pivot.
  viewer.send(R"({"type":"drag","particle":3,"target":[0,0,2.6]})");
  viewer.send(R"({"type":"drag","particle":0,"target":[0,0,9]})");  // fixed: ignored
  viewer.send("not json");                                           // ignored
  for (int k = 0; k < 20000 && world.state().time < 1.5; ++k) {
    world.step(1e-4);
    view.afterStep(world);
  }
  EXPECT_GT(view.dragWork(), 0.0);
  EXPECT_NEAR(world.energy().external, view.dragWork(), 1e-9 * view.dragWork());
  EXPECT_GT(world.state().position[3].z, 2.0);
  // Released (once the message came): no more work.
  viewer.send(R"({"type":"release"})");
  for (int k = 0; k < 5000 && view.dragging(); ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    world.step(1e-4);
    view.afterStep(world);
  }
  ASSERT_FALSE(view.dragging());
  const double released = view.dragWork();
  for (int k = 0; k < 100; ++k) {
    world.step(1e-4);
    view.afterStep(world);
  }
  EXPECT_EQ(view.dragWork(), released);
  EXPECT_EQ(view.outcomes(world)["live"]["drags"], 1);
}

TEST(LiveView, APortInUseIsAClearError) {
  const Scene scene = pendulum();
  LiveView first(scene, scene.initial, everyStep());
  LiveViewSettings same = everyStep();
  same.port = std::stoi(first.url().substr(17));
  try {
    LiveView second(scene, scene.initial, same);
    FAIL() << "a second server on the same port";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(same.port)), std::string::npos) << e.what();
  }
}

#else

TEST(LiveView, NotBuilt) {
  EXPECT_FALSE(output::liveServerAvailable());
  GTEST_SKIP() << "robophi was built without the live view (Boost.Beast: libboost-dev)";
}

#endif

}  // namespace
}  // namespace robophi
