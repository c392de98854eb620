// Counts heap allocations made while a scope is open, so tests can prove that a
// core or macro call allocates nothing. The test programs are linked with
// -Wl,--wrap=malloc,calloc,realloc,free and operator new is replaced, so every
// allocation from the program's own objects (including Eigen's inline code) goes
// through the counter.
#pragma once

#include <cstddef>

namespace trueaxis::test {

std::size_t allocation_count();

// Allocations made between construction and count().
class AllocationScope {
 public:
  AllocationScope() : start_(allocation_count()) {}
  std::size_t count() const { return allocation_count() - start_; }

 private:
  std::size_t start_;
};

}  // namespace trueaxis::test
