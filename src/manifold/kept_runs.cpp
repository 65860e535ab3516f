#include "manifold/kept_runs.h"

#include <algorithm>

namespace matlas {

KeptRuns kept_runs(const std::uint8_t* kept, std::size_t count, std::size_t range) {
  KeptRuns r;
  for (std::size_t r0 = 0; r0 < count; r0 += range) {
    r.range_begin.push_back(r.runs.size());
    const std::size_t r1 = std::min(count, r0 + range);
    for (std::size_t j = r0; j < r1;) {
      if (!kept[j]) {
        ++j;
        continue;
      }
      const std::size_t start = j;
      while (j < r1 && kept[j]) ++j;
      r.runs.push_back({start, j - start, r.kept});
      r.kept += j - start;
    }
  }
  r.range_begin.push_back(r.runs.size());
  return r;
}

}  // namespace matlas
