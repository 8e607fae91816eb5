// Synthesises a small rigid sequence, reconstructs it and checks e3D: proves
// the installed headers, library and dependencies are complete.
#include <nrsfm/core/eval/metrics.h>
#include <nrsfm/core/synthetic/synthetic.h>
#include <nrsfm/solvers/pipeline/reconstruct.h>

#include <iostream>

int main() {
  nrsfm::RandomBasisOptions options;
  options.num_frames = 30;
  options.num_points = 12;
  options.num_bases = 1;
  nrsfm::SyntheticSequence sequence;
  if (!nrsfm::GenerateRandomBasis(options, &sequence).ok()) return 1;
  nrsfm::ReconstructOptions reconstruct_options;
  reconstruct_options.start.num_bases = 1;
  nrsfm::ReconstructResult result;
  const nrsfm::Status status =
      nrsfm::Reconstruct(reconstruct_options, sequence.measurements, &result);
  if (!status.ok()) {
    std::cerr << status.message() << "\n";
    return 1;
  }
  const double e3d = nrsfm::ComputeE3D(nrsfm::CameraFrameShapes(sequence.truth),
                                       nrsfm::CameraFrameShapes(result.model));
  std::cout << "consumer: e3D " << e3d << "\n";
  return e3d < 1e-6 ? 0 : 1;
}
