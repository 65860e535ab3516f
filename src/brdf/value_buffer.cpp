#include "brdf/value_buffer.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "core/huge_pages.h"

namespace matlas {

namespace {
double* allocate(std::size_t size) {
  return size == 0 ? nullptr : static_cast<double*>(allocate_huge_pages(size * sizeof(double)));
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
