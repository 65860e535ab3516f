#include "brdf/value_buffer.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <new>

#include "core/huge_pages.h"

namespace matlas {

namespace {
double* allocate(std::size_t size) {
  if (size == 0) return nullptr;
  const std::size_t bytes = size * sizeof(double);
  const std::size_t alignment = bytes >= kHugePageBytes ? kHugePageBytes : 64;
  const std::size_t rounded = (bytes + alignment - 1) / alignment * alignment;
  void* p = std::aligned_alloc(alignment, rounded);
  if (!p) throw std::bad_alloc();
  advise_huge_pages(p, rounded);
  return static_cast<double*>(p);
}
}  // namespace

void ValueBuffer::Free::operator()(double* p) const { std::free(p); }

ValueBuffer::ValueBuffer(std::size_t size, Uninitialized) : data_(allocate(size)), size_(size) {}

ValueBuffer::ValueBuffer(std::size_t size) : ValueBuffer(size, Uninitialized{}) {
  std::fill(begin(), end(), 0.0);
}

ValueBuffer::ValueBuffer(const ValueBuffer& other) : ValueBuffer(other.size_, Uninitialized{}) {
  if (size_) std::memcpy(data(), other.data(), size_ * sizeof(double));
}

ValueBuffer& ValueBuffer::operator=(const ValueBuffer& other) {
  if (this != &other) *this = ValueBuffer(other);
  return *this;
}

}  // namespace matlas
