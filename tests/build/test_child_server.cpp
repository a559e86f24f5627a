// ChildServer (src/build/child_process.h): the long-lived child that reads mesh
// files for a process. One child answers many requests; a crash, an abort or a
// hang ends only that child, the request is answered as such, and the next
// request forks a new one; a child killed while it waits is replaced; it works
// in the asker's folder and keeps none of the asker's files open.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

#include "build/child_process.h"
#include "test_files.h"

namespace robophi::build {
namespace {

namespace fs = std::filesystem;

// The test's handler: "folder" answers the working folder, "crash" dies of a
// segmentation fault, "abort" aborts, "hang" sleeps past any deadline, "fd N"
// answers whether file descriptor N is open, anything else is echoed.
std::string childServerTestHandler(const std::string& request) {
  if (request == "folder") return fs::current_path().string();
  if (request == "crash") std::raise(SIGSEGV);
  if (request == "abort") std::abort();
  if (request == "hang") std::this_thread::sleep_for(std::chrono::seconds(60));
  if (request.rfind("fd ", 0) == 0)
    return fcntl(std::stoi(request.substr(3)), F_GETFD) >= 0 ? "open" : "closed";
  return "echo " + request;
}

TEST(ChildServer, OneChildAnswersManyRequests) {
  ChildServer server(&childServerTestHandler);
  EXPECT_EQ(server.pid(), -1);  // forked at the first request
  const ChildOutcome first = server.ask("a", 10);
  ASSERT_EQ(first.kind, ChildOutcome::kAnswered);
  EXPECT_EQ(first.answer, "echo a");
  const pid_t child = server.pid();
  EXPECT_GT(child, 0);
  for (int i = 0; i < 50; ++i) {
    const std::string request(static_cast<std::size_t>(i) * 4096, 'x');  // up to 200 kB
    const ChildOutcome outcome = server.ask(request, 10);
    ASSERT_EQ(outcome.kind, ChildOutcome::kAnswered) << i;
    EXPECT_EQ(outcome.answer, "echo " + request) << i;
  }
  EXPECT_EQ(server.pid(), child);
}

TEST(ChildServer, ACrashOrAnAbortEndsOnlyTheChildAndTheNextRequestIsAnswered) {
  ChildServer server(&childServerTestHandler);
  ASSERT_EQ(server.ask("a", 10).kind, ChildOutcome::kAnswered);
  const pid_t before = server.pid();
  const ChildOutcome crashed = server.ask("crash", 10);
  EXPECT_EQ(crashed.kind, ChildOutcome::kCrashed);
  EXPECT_EQ(crashed.signal, SIGSEGV);
  EXPECT_EQ(crashed.how(), "Segmentation fault");
  EXPECT_TRUE(crashed.answer.empty());
  EXPECT_EQ(server.pid(), -1);
  const ChildOutcome aborted = server.ask("abort", 10);
  EXPECT_EQ(aborted.kind, ChildOutcome::kCrashed);
  EXPECT_EQ(aborted.signal, SIGABRT);
  const ChildOutcome next = server.ask("b", 10);
  ASSERT_EQ(next.kind, ChildOutcome::kAnswered);
  EXPECT_EQ(next.answer, "echo b");
  EXPECT_NE(server.pid(), before);
}

TEST(ChildServer, ARequestPastItsDeadlineIsAHangAndTheChildIsKilled) {
  ChildServer server(&childServerTestHandler);
  const auto start = std::chrono::steady_clock::now();
  const ChildOutcome hung = server.ask("hang", 1);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(hung.kind, ChildOutcome::kTimedOut);
  EXPECT_EQ(hung.how(), "a hang");
  EXPECT_LT(seconds, 30.0);  // the deadline, not the handler's 60 s
  EXPECT_EQ(server.pid(), -1);
  EXPECT_EQ(server.ask("c", 10).answer, "echo c");
}

TEST(ChildServer, AChildKilledWhileItWaitsIsReplaced) {
  ChildServer server(&childServerTestHandler);
  ASSERT_EQ(server.ask("a", 10).kind, ChildOutcome::kAnswered);
  const pid_t before = server.pid();
  ASSERT_EQ(kill(before, SIGKILL), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const ChildOutcome next = server.ask("d", 10);
  ASSERT_EQ(next.kind, ChildOutcome::kAnswered);
  EXPECT_EQ(next.answer, "echo d");
  EXPECT_NE(server.pid(), before);
}

TEST(ChildServer, ItWorksInTheAskersFolderAndHoldsNoneOfItsFiles) {
  const fs::path folder = testing::makeTempFolder("robophi_child_server_");
  const fs::path before = fs::current_path();
  const int held = open(before.c_str(), O_RDONLY | O_DIRECTORY);  // opened before the fork
  ASSERT_GE(held, 0);
  ChildServer server(&childServerTestHandler);
  EXPECT_EQ(server.ask("folder", 10).answer, before.string());
  EXPECT_EQ(server.ask("fd " + std::to_string(held), 10).answer, "closed");
  EXPECT_EQ(server.ask("fd 2", 10).answer, "open");  // its standard streams are kept
  fs::current_path(folder);
  const ChildOutcome moved = server.ask("folder", 10);
  fs::current_path(before);
  EXPECT_EQ(moved.answer, fs::canonical(folder).string());
  close(held);
  fs::remove_all(folder);
}

}  // namespace
}  // namespace robophi::build
