#include "manifold/export.h"

#include <algorithm>

namespace matlas {

BrdfTable export_table(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& w, ExportStats* stats) {
  BrdfTable table = model.table(w);
  ExportStats s;
  const std::size_t bins = table.bins();
  auto stored = table.stored();
  for (std::size_t v = 0; v < stored.size(); ++v) {
    if (!model.kept(v)) {
      ++s.missing;  // already -1
    } else if (stored[v] < 0.0) {
      ++s.clamped;
      s.most_negative = std::min(s.most_negative, stored[v] * BrdfTable::kChannelScale[v / bins]);
      stored[v] = 0.0;
    }
  }
  if (stats) *stats = s;
  return table;
}

}  // namespace matlas
