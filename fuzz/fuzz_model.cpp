// Fuzz target: the model loader (safetensors header, metadata, tensor shapes, checksum, column
// map), then queries on whatever it accepts.
#include <cstddef>
#include <cstdint>

#include "core/error.h"
#include "manifold/model.h"
#include "memfile.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  matlas::fuzz::MemFile file(data, size);
  try {
    const matlas::Model model = matlas::Model::open(file.path());
    const Eigen::VectorXd x = model.latent().row(0).transpose();
    const Eigen::VectorXd w = model.weights(x);
    (void)model.variance(x);
    const std::size_t values = 3 * model.dims().bins();
    for (std::size_t v = 0; v < values; v += 1 + values / 64) (void)model.value(v, w);
    (void)model.lookup(matlas::Vec3(0, 0, 1), matlas::Vec3(0.3, 0, 0.95), w);
    (void)model.albedo_curve(w);
    if (values <= (1u << 16)) (void)model.table(w);
  } catch (const matlas::Error&) {
  }
  return 0;
}
