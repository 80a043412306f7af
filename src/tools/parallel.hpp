// Runs fn(i) for i in [0, count) on `jobs` threads (the tools' case runner).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace cws_tools {

template <class Fn>
void forEachParallel(std::size_t count, int jobs, Fn fn) {
  std::atomic<std::size_t> next{0};
  std::vector<std::thread> workers;
  for (int j = 0; j < std::max(1, jobs); ++j) {
    workers.emplace_back([&] {
      for (std::size_t i = next++; i < count; i = next++) fn(i);
    });
  }
  for (std::thread& w : workers) w.join();
}

}  // namespace cws_tools
