#pragma once
// S += A A^T for a row-major block A (n materials x k columns): the Gram update of a build pass.
// OpenBLAS's dsyrk does not speed up with threads for this thin shape (n ~ 100, k ~ 30000), so the
// k columns are split into chunks handed out to the workers as they become free (the pass's
// reader thread competes for the cores), each chunk a single-threaded dsyrk into its own n x n
// partial; the partials are summed in chunk order, so the result does not depend on scheduling.
// Only the upper triangle of S is updated.
#include <Eigen/Core>

#include "manifold/column_blocks.h"

namespace matlas {

void add_gram_upper(const BlockMatrix& a, Eigen::MatrixXd& upper);

/// Copies the upper triangle of S into its lower triangle.
void symmetrize_from_upper(Eigen::MatrixXd& s);

}  // namespace matlas
