// The allocation budget of the fuzz targets: while a target reads an input
// of N bytes, one allocation of more than InputArrayBudget(N) = 64 MB +
// 1032 · N bytes (core/io/input_budget.h: what a file of N bytes may make the
// readers hold) is a finding. The hook prints the sizes and the stack and
// aborts, so libFuzzer keeps the input as a crash-* artifact.
//
// The hook sees only allocations that succeed. In the strict-allocation
// mode (tests/fuzz/CMakeLists.txt, NRSFM_FUZZ_STRICT_ALLOC) ASan lets every
// allocation succeed (no allocator_may_return_null, no
// max_allocation_size_mb), so each one over the budget is reported; with
// the old ASAN_OPTIONS=allocator_may_return_null=1:max_allocation_size_mb=64
// an allocation over 64 MB fails quietly instead and the hook never fires.
#ifndef NRSFM_TESTS_FUZZ_ALLOCATION_BUDGET_H_
#define NRSFM_TESTS_FUZZ_ALLOCATION_BUDGET_H_

#include <sanitizer/allocator_interface.h>
#include <sanitizer/common_interface_defs.h>

#include <atomic>
#include <cstddef>
#include <cstdio>
#include <cstdlib>

#include "core/io/input_budget.h"

namespace nrsfm {
namespace fuzz {

inline std::atomic<std::size_t> g_budget_limit{0};  // 0: no input being read
inline std::atomic<std::size_t> g_budget_input_size{0};

inline void BudgetMallocHook(const volatile void* /*pointer*/,
                             std::size_t size) {
  const std::size_t limit = g_budget_limit.load(std::memory_order_relaxed);
  if (limit == 0 || size <= limit) return;
  g_budget_limit.store(0);  // what follows allocates too
  std::fprintf(stderr,
               "==nrsfm allocation budget: one allocation of %zu bytes while "
               "reading an input "
               "of %zu bytes (budget 64 MB + 1032 x %zu = %zu bytes)\n",
               size, g_budget_input_size.load(), g_budget_input_size.load(),
               limit);
  __sanitizer_print_stack_trace();
  std::abort();
}

inline void BudgetFreeHook(const volatile void* /*pointer*/) {}

// Holds the budget of one input for the lifetime of the object: the first
// statement of each LLVMFuzzerTestOneInput.
class AllocationBudget {
 public:
  explicit AllocationBudget(std::size_t input_size) {
    static const bool installed = __sanitizer_install_malloc_and_free_hooks(
                                      &BudgetMallocHook, &BudgetFreeHook) != 0;
    if (!installed) std::abort();  // a broken set-up, not a finding
    g_budget_input_size.store(input_size);
    g_budget_limit.store(
        static_cast<std::size_t>(InputArrayBudget(input_size)));
  }
  ~AllocationBudget() { g_budget_limit.store(0); }
  AllocationBudget(const AllocationBudget&) = delete;
  AllocationBudget& operator=(const AllocationBudget&) = delete;
};

}  // namespace fuzz
}  // namespace nrsfm

#endif  // NRSFM_TESTS_FUZZ_ALLOCATION_BUDGET_H_
