// A stage that throws must not cut short the parallel work of the other stages (apps/pipeline_stage.hpp).
#include "pipeline/pipeline_stage.hpp"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

namespace cleanmap::pipeline {
namespace {

TEST(PipelineStage, AThrowingStageLeavesTheOthersParallelWorkWholeAndIsRethrownAfter) {
  // Item 2 is inside a long parallel_for in the second stage when the first throws on item 3.
  // With plain tbb::make_filter the exception cancels the pipeline's task group and that
  // parallel_for returns with most of its range never run (what crashed describe_objects).
  constexpr int kRange = 400;
  std::atomic<bool> looping{false};
  std::mutex m;
  std::vector<int> done;  // per item that entered the second stage: iterations run
  StageFailure failure;
  int next = 0;
  const auto run = [&] {
    run_pipeline_stages(
        4, failure,
        guarded_filter<void, int>(tbb::filter_mode::serial_in_order, failure,
                                  [&](tbb::flow_control& fc) {
                                    if (next == 10) fc.stop();
                                    return next++;
                                  }) &
            guarded_filter<int, int>(tbb::filter_mode::serial_in_order, failure,
                                     [&](int i) {
                                       if (i == 3) {
                                         const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
                                         while (!looping && std::chrono::steady_clock::now() < until) std::this_thread::yield();
                                         throw std::runtime_error("bad scan 3");
                                       }
                                       return i;
                                     }) &
            guarded_filter<int, void>(tbb::filter_mode::serial_in_order, failure, [&](int i) {
              std::atomic<int> count{0};
              tbb::parallel_for(0, kRange, [&](int) {
                looping = true;
                std::this_thread::sleep_for(std::chrono::microseconds(500));
                ++count;
              });
              std::lock_guard<std::mutex> lock(m);
              done.push_back(count);
              (void)i;
            }));
  };
  EXPECT_THROW(run(), std::runtime_error);
  ASSERT_FALSE(done.empty());
  for (const int d : done) EXPECT_EQ(d, kRange);  // every loop that started ran to its end
  EXPECT_LE(done.size(), 3u);                      // nothing after the failure
}

}  // namespace
}  // namespace cleanmap::pipeline
