// core/blas.h: the kernel choice from the processor's features, the loaded library running the
// chosen kernels (unless OPENBLAS_CORETYPE was set by the user), the environment left as it was,
// and the bound routines computing what they should.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/Core>

#include "core/blas.h"

namespace matlas {
namespace {

TEST(BlasKernel, FollowsTheProcessorsFeatures) {
  EXPECT_EQ(blas::kernel_for(true, true), "SkylakeX");
  EXPECT_EQ(blas::kernel_for(true, false), "SkylakeX");
  EXPECT_EQ(blas::kernel_for(false, true), "Haswell");
  EXPECT_EQ(blas::kernel_for(false, false), "");
}

TEST(BlasKernel, TheLoadedLibraryRunsTheChosenKernelsAndTheEnvironmentIsUnchanged) {
  const char* user_choice = std::getenv("OPENBLAS_CORETYPE");
  const std::string before = user_choice ? user_choice : "";
  const blas::Library& lib = blas::openblas();
  const char* after = std::getenv("OPENBLAS_CORETYPE");
  EXPECT_EQ(after ? std::string(after) : std::string(), before);
  const std::string wanted = blas::kernel_for_this_processor();
  const std::string running = lib.corename();
  if (user_choice != nullptr || wanted.empty()) GTEST_SKIP() << "OpenBLAS chose its kernels itself: " << running;
  // OpenBLAS spells the names in its own case ("Skylakex" / "SkylakeX" across versions).
  auto lower = [](std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
  };
  EXPECT_EQ(lower(running), lower(wanted)) << blas::description();
  EXPECT_NE(blas::description().find("OpenBLAS"), std::string::npos);
}

TEST(BlasKernel, ANoteSaysWhenTheUsersVariableOverridesMatlassChoice) {
  EXPECT_EQ(blas::kernel_override_note(nullptr, "SkylakeX"), "");   // unset: matlas chooses
  EXPECT_EQ(blas::kernel_override_note("skylakex", "SkylakeX"), "");  // the same kernels, any case
  EXPECT_EQ(blas::kernel_override_note("Haswell", ""), "");          // matlas has no choice to offer
  const std::string note = blas::kernel_override_note("Haswell", "SkylakeX");
  EXPECT_NE(note.find("OPENBLAS_CORETYPE=Haswell"), std::string::npos) << note;
  EXPECT_NE(note.find("SkylakeX"), std::string::npos) << note;
  EXPECT_NE(note.find("unset"), std::string::npos) << note;
}

TEST(BlasRoutines, ComputeWhatEigenComputes) {
  const blas::Library& lib = blas::openblas();
  const int n = 37, k = 11;
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, k), b = Eigen::MatrixXd::Random(k, n);
  Eigen::MatrixXd c(n, n);
  lib.dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n, n, k, 1.0, a.data(), n, b.data(), k, 0.0, c.data(), n);
  EXPECT_LT((c - a * b).norm(), 1e-12 * (a * b).norm());

  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(n, n);
  lib.dsyrk(CblasColMajor, CblasLower, CblasNoTrans, n, k, 1.0, a.data(), n, 0.0, s.data(), n);
  const Eigen::MatrixXd aat = a * a.transpose();
  EXPECT_LT((s.triangularView<Eigen::Lower>().toDenseMatrix() - aat.triangularView<Eigen::Lower>().toDenseMatrix()).norm(),
            1e-12 * aat.norm());

  // K = A A^T + I: Cholesky and the inverse from it against Eigen's.
  const Eigen::MatrixXd K = aat + Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd L = K;
  int info = -1;
  lib.dpotrf("L", &n, L.data(), &n, &info);
  ASSERT_EQ(info, 0);
  const Eigen::MatrixXd eigen_l = K.llt().matrixL();
  EXPECT_LT((L.triangularView<Eigen::Lower>().toDenseMatrix() - eigen_l).norm(), 1e-12 * eigen_l.norm());
  const Eigen::MatrixXd y = eigen_l.triangularView<Eigen::Lower>().solve(b.transpose());

  // dsymm and dtrmm against Eigen.
  Eigen::MatrixXd sb(n, k);
  lib.dsymm(CblasColMajor, CblasLeft, CblasLower, n, k, 1.0, K.data(), n, y.data(), n, 0.0, sb.data(), n);
  EXPECT_LT((sb - K * y).norm(), 1e-12 * (K * y).norm());
  Eigen::MatrixXd ly = y;
  lib.dtrmm(CblasColMajor, CblasLeft, CblasLower, CblasNoTrans, CblasNonUnit, n, k, 1.0, L.data(), n, ly.data(), n);
  EXPECT_LT((ly - b.transpose()).norm(), 1e-10 * b.norm());

  // A matrix that is not positive definite is reported, not factored.
  Eigen::MatrixXd bad = -Eigen::MatrixXd::Identity(n, n);
  lib.dpotrf("L", &n, bad.data(), &n, &info);
  EXPECT_GT(info, 0);
}

/// The recursive inverse gives K^-1 (Eigen's, to rounding) at every size around the recursion's
/// leaf and halving points, and leaves the strict upper triangle alone.
TEST(Blas, InverseFromCholeskyIsTheInverse) {
  const blas::Library& lib = blas::openblas();
  for (const int n : {1, 2, 15, 16, 17, 31, 33, 64, 100, 129}) {
    SCOPED_TRACE(n);
    const Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n);
    const Eigen::MatrixXd K = a * a.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
    Eigen::MatrixXd got = K;
    int info = -1;
    lib.dpotrf("L", &n, got.data(), &n, &info);
    ASSERT_EQ(info, 0);
    for (Eigen::Index j = 1; j < n; ++j)
      for (Eigen::Index i = 0; i < j; ++i) got(i, j) = 7.0;  // must survive
    ASSERT_EQ(blas::inverse_from_cholesky(n, got.data(), n), 0);
    const Eigen::MatrixXd want = K.inverse();
    const Eigen::MatrixXd full = got.selfadjointView<Eigen::Lower>();
    EXPECT_LT((full - want).norm(), 1e-9 * want.norm());
    EXPECT_LT((full * K - Eigen::MatrixXd::Identity(n, n)).norm(), 1e-8 * n);
    for (Eigen::Index j = 1; j < n; ++j)
      for (Eigen::Index i = 0; i < j; ++i) EXPECT_EQ(got(i, j), 7.0);
  }
}

}  // namespace
}  // namespace matlas
