// robophi bench as a user runs it (docs/performance.md): each run reads its
// energy account and prints it with its figures; a run whose account passes
// the bound of `robophi run` is not ok.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;
using testing::readText;

TEST(BenchCommand, EachRunCarriesItsEnergyAccount) {
  const fs::path root = testing::makeTempFolder("robophi_bench_");
  const std::string command = std::string(ROBOPHI_BINARY) +
                              " bench --quick --json --record '' --threads 1 --filter PILE-1000 > " +
                              (root / "out.json").string() + " 2> " + (root / "err.txt").string();
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << readText(root / "err.txt");
  const auto doc = nlohmann::json::parse(readText(root / "out.json"));
  const auto& results = doc.at("results");
  ASSERT_EQ(results.size(), 2u);  // PILE-1000 and PILE-1000-ATS
  for (const auto& r : results) {
    EXPECT_EQ(r.at("status"), "ok") << r.dump();
    const double error = r.at("energy_account_error").get<double>();
    EXPECT_TRUE(std::isfinite(error) && error >= 0.0 && error < 0.05) << r.dump();
    EXPECT_LE(r.at("energy_account_change_second_half").get<double>(), error * 2.0 + 1e-12);
    EXPECT_GE(r.at("steps_over_contact_limit").get<long long>(), 0);
  }
  // The adaptive run keeps below the contacts' limit; it is counted for constant steps.
  EXPECT_EQ(results[1].at("steps_over_contact_limit").get<long long>(), 0);
  fs::remove_all(root);
}

}  // namespace
}  // namespace robophi
