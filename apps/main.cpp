#include <tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>

#include "apps/commands.hpp"
#include "pipeline/interrupt.hpp"
#include "io/error.hpp"

namespace {
// Exit code of a command line that cannot be parsed (README: "Exit codes").
constexpr int kUsageError = 2;
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"cleanmap: clean static maps from raw lidar logs (spatiotemporal normals)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "cleanmap 0.1.0");
  int threads = 0;
  // At most 1024: TBB gives every worker its own stack and arena slot up front, and 2^31 of them
  // ended in std::bad_alloc (issue 45); no machine this runs on has more hardware threads.
  app.add_option("--threads", threads, "Worker threads (0 = all cores), in [0, 1024]")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  cleanmap::app::register_demo(app);
  cleanmap::app::register_score(app);
  cleanmap::app::register_odometry(app);
  cleanmap::app::register_run(app);
  cleanmap::app::register_eval(app);
  cleanmap::app::register_compare(app);
  cleanmap::app::register_report(app);
  cleanmap::app::register_config(app);
  // Options of the top level (--threads) work after a subcommand too: cleanmap run --threads 2.
  std::function<void(CLI::App*)> fall = [&](CLI::App* a) {
    for (auto* sub : a->get_subcommands([](CLI::App*) { return true; })) {
      sub->fallthrough();
      fall(sub);
    }
  };
  fall(&app);
  std::unique_ptr<tbb::global_control> limit;
  app.parse_complete_callback([&] {
    if (threads > 0) {
      limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                    static_cast<std::size_t>(threads));
    }
  });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // A word where the command goes that names none (issue 45: `cleanmap frobnicate` said only
    // "A subcommand is required"): name the word and list the commands.
    if (app.get_subcommands().empty()) {
      for (int i = 1; i < argc; ++i) {
        const std::string word = argv[i];
        if (word == "--threads") ++i;  // its value
        if (word.empty() || word[0] == '-') continue;
        std::string commands;
        for (const auto* sub : app.get_subcommands([](CLI::App*) { return true; })) {
          commands += (commands.empty() ? "" : ", ") + sub->get_name();
        }
        std::fprintf(stderr, "cleanmap: '%s' is not a command; the commands: %s (cleanmap --help)\n",
                     word.c_str(), commands.c_str());
        return kUsageError;
      }
    }
    // --help and --version end here with 0; every usage error exits 2 (CLI11's own codes,
    // 104-114, told a script nothing it could rely on).
    return app.exit(e) == 0 ? 0 : kUsageError;
  } catch (const cleanmap::pipeline::Interrupted& e) {
    std::fprintf(stderr, "\ncleanmap: %s\n", e.what());
    return 128 + e.signal;  // as a shell reports a process ended by the signal: 130 SIGINT, 143 SIGTERM
  } catch (const cleanmap::Error& e) {
    std::fprintf(stderr, "cleanmap: error: %s\n", e.what());
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    std::fprintf(stderr, "cleanmap: error: %s\n", cleanmap::describe(e).c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cleanmap: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
