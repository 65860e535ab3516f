#pragma once
// The measured object's materials, seen by the path tracer: K tabulated BRDFs evaluated together
// at one MERL bin (nearest-bin lookup, as MERL's reference reader; missing values read 0).
#include <cstddef>
#include <vector>

#include "brdf/brdf_table.h"

namespace matlas::pathtrace {

class TableBank {
public:
  virtual ~TableBank() = default;
  virtual int count() const = 0;
  virtual const MerlDims& dims() const = 0;
  /// out[3 k + c] = physical value of channel c of material k at `bin`, for k < count().
  /// Called concurrently from several threads.
  virtual void eval_bin(std::size_t bin, double* out) const = 0;
};

/// A bank of tables held elsewhere (all of the same dimensions).
class TableListBank final : public TableBank {
public:
  /// Throws matlas::Error when the list is empty or the tables' dimensions differ.
  explicit TableListBank(std::vector<const BrdfTable*> tables);
  int count() const override { return static_cast<int>(tables_.size()); }
  const MerlDims& dims() const override { return tables_.front()->dims(); }
  void eval_bin(std::size_t bin, double* out) const override;

private:
  std::vector<const BrdfTable*> tables_;
};

}  // namespace matlas::pathtrace
