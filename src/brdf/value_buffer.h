#pragma once
// ValueBuffer: the storage of a BrdfTable (35 MB at MERL size). Allocated 2 MiB-aligned with
// transparent huge pages requested, and left uninitialised when the caller is about to overwrite
// it (reading a file): page faults and zero-filling otherwise cost more than the read itself.
#include <cstddef>
#include <memory>
#include <span>

namespace matlas {

class ValueBuffer {
public:
  ValueBuffer() = default;
  /// `size` doubles, all zero.
  explicit ValueBuffer(std::size_t size);
  struct Uninitialized {};
  /// `size` doubles with unspecified values.
  ValueBuffer(std::size_t size, Uninitialized);

  ValueBuffer(const ValueBuffer& other);
  ValueBuffer& operator=(const ValueBuffer& other);
  ValueBuffer(ValueBuffer&&) noexcept = default;
  ValueBuffer& operator=(ValueBuffer&&) noexcept = default;

  std::size_t size() const { return size_; }
  double* data() { return data_.get(); }
  const double* data() const { return data_.get(); }
  double& operator[](std::size_t i) { return data_[i]; }
  double operator[](std::size_t i) const { return data_[i]; }
  double* begin() { return data(); }
  double* end() { return data() + size_; }
  const double* begin() const { return data(); }
  const double* end() const { return data() + size_; }
  operator std::span<double>() { return {data(), size_}; }
  operator std::span<const double>() const { return {data(), size_}; }

private:
  struct Free {
    void operator()(double* p) const;
  };
  std::unique_ptr<double[], Free> data_;
  std::size_t size_ = 0;
};

}  // namespace matlas
