/* The row a new kernel adds to src/kernels/kernel_list.h, here for the test-only kernel
 * test_tent and appended from outside: CMake forces this file into every source of
 * test_kernel_extra (which compiles src/kernels/ again), never into spam-ark. The header
 * line is what the row's #include in kernel_list.h would be. */
#define SPAM_KERNEL_LIST_EXTRA(X, ctx) X(ctx, TEST_TENT, test_tent, TestTent)
#define SPAM_KERNEL_EXTRA_HEADER <kernel_test_tent.h>
