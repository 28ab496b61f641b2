#pragma once
// Counting replacements of the global operator new and delete, for the tests that check that a
// path allocates nothing once warm: every allocation through operator new (std::vector and the
// other standard containers; Eigen's dynamic matrices use malloc and are not seen) adds one to
// cw4d::test::allocation_count(). Every replaceable form is replaced -- plain, array, aligned,
// nothrow and their combinations -- each allocating with malloc (or aligned_alloc) and freeing
// with free, so that no allocation escapes the count and a sanitizer's check that each
// allocation is released by the matching form never sees a form of its own freed by one of ours.
//
// The operators are definitions (a replacement cannot be inline): include this header in exactly
// one translation unit of a test executable (a second one fails to link).
#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

namespace cw4d::test {

inline std::atomic<std::size_t> g_counted_allocations{0};

/// The allocations through operator new so far in this program.
inline std::size_t allocation_count() {
  return g_counted_allocations.load(std::memory_order_relaxed);
}

namespace counting_new_detail {

inline void* counted(std::size_t n) {
  g_counted_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(n == 0 ? 1 : n);
}

inline void* counted_aligned(std::size_t n, std::align_val_t a) {
  g_counted_allocations.fetch_add(1, std::memory_order_relaxed);
  const auto al = static_cast<std::size_t>(a);
  // (aligned_alloc wants a size that is a multiple of the alignment)
  return std::aligned_alloc(al, (n == 0 ? al : (n + al - 1) / al * al));
}

}  // namespace counting_new_detail
}  // namespace cw4d::test

void* operator new(std::size_t n) {
  if (void* p = cw4d::test::counting_new_detail::counted(n)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  if (void* p = cw4d::test::counting_new_detail::counted(n)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t n, std::align_val_t a) {
  if (void* p = cw4d::test::counting_new_detail::counted_aligned(n, a)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n, std::align_val_t a) {
  if (void* p = cw4d::test::counting_new_detail::counted_aligned(n, a)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  return cw4d::test::counting_new_detail::counted(n);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  return cw4d::test::counting_new_detail::counted(n);
}
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return cw4d::test::counting_new_detail::counted_aligned(n, a);
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return cw4d::test::counting_new_detail::counted_aligned(n, a);
}
// (GCC at -O1 and above takes these free() calls for a mismatch with operator new: here every
// operator new is malloc or aligned_alloc, above)
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  std::free(p);
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
