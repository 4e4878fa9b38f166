#pragma once

#include <tbb/parallel_pipeline.h>

#include <atomic>
#include <exception>
#include <mutex>
#include <type_traits>
#include <utility>

namespace cleanmap::pipeline {

// An exception thrown by one stage of a TBB pipeline cancels the pipeline's task group, and with
// it every parallel algorithm still running inside another stage: a parallel_for there returns
// with part of its range never run, and that stage goes on with what it half built. CI saw it:
// a truncated scan's error arrived while the scorer was describing a scan's objects, which then
// read a null pointer (segfault in describe_objects, once in several hundred runs). So a
// stage's exception is kept instead: the input stops, the items in flight pass the remaining
// stages untouched, and the first exception is rethrown once the pipeline has returned.
class StageFailure {
 public:
  bool failed() const { return failed_.load(std::memory_order_acquire); }
  void record(std::exception_ptr e) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!first_) first_ = std::move(e);
    failed_.store(true, std::memory_order_release);
  }
  // After the pipeline has returned (no stage runs any more).
  void rethrow_if_failed() const {
    if (first_) std::rethrow_exception(first_);
  }

 private:
  std::atomic<bool> failed_{false};
  std::mutex mutex_;
  std::exception_ptr first_;
};

// tbb::make_filter whose body never throws out of the stage: its exception goes to `failure`.
// Once anything failed, the body no longer runs (an input stage stops the pipeline; the others
// hand on an empty item).
template <typename In, typename Out, typename Body>
tbb::filter<In, Out> guarded_filter(tbb::filter_mode mode, StageFailure& failure, Body body) {
  if constexpr (std::is_void_v<In>) {
    return tbb::make_filter<In, Out>(mode, [&failure, body](tbb::flow_control& fc) -> Out {
      if (!failure.failed()) {
        try {
          Out out = body(fc);
          if (!failure.failed()) return out;
        } catch (...) {
          failure.record(std::current_exception());
        }
      }
      fc.stop();
      return Out();
    });
  } else {
    return tbb::make_filter<In, Out>(mode, [&failure, body](In in) -> Out {
      if constexpr (std::is_void_v<Out>) {
        if (failure.failed()) return;
        try {
          body(std::move(in));
        } catch (...) {
          failure.record(std::current_exception());
        }
      } else {
        if (failure.failed()) return Out();
        try {
          return body(std::move(in));
        } catch (...) {
          failure.record(std::current_exception());
          return Out();
        }
      }
    });
  }
}

// tbb::parallel_pipeline over guarded stages; rethrows the first stage's exception after it.
template <typename Filter>
void run_pipeline_stages(std::size_t tokens, StageFailure& failure, const Filter& stages) {
  tbb::parallel_pipeline(tokens, stages);
  failure.rethrow_if_failed();
}

}  // namespace cleanmap::pipeline
