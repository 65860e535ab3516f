#include "pathtrace/table_bank.h"

#include "core/error.h"

namespace matlas::pathtrace {

TableListBank::TableListBank(std::vector<const BrdfTable*> tables) : tables_(std::move(tables)) {
  if (tables_.empty()) throw Error("a table bank needs at least one table");
  for (const BrdfTable* t : tables_)
    if (!(t->dims() == tables_.front()->dims())) throw Error("the tables of a bank differ in dimensions");
}

void TableListBank::eval_bin(std::size_t bin, double* out) const {
  for (std::size_t k = 0; k < tables_.size(); ++k) {
    const Rgb v = tables_[k]->bin_rgb(bin);
    for (int c = 0; c < 3; ++c) out[3 * k + static_cast<std::size_t>(c)] = v[c];
  }
}

}  // namespace matlas::pathtrace
