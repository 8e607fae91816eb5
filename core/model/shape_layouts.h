// The layouts in which datasets store per-frame 3-D points (docs/guide.md,
// "Input formats"), converted to one 3 × P matrix per frame.
//
//   interleaved  3F × P   rows x_t, y_t, z_t of frame t at 3t, 3t+1, 3t+2
//                         (Akhter et al.'s S)
//   block        3F × P   rows t, F+t, 2F+t are x_t, y_t, z_t
//                         (Torresani et al.'s P3_gt)
//   array3       3 × P × F, slice t = frame t (the X of many datasets)
//
// `name` (e.g. "face.mat: P3_gt") is used in error messages.
#ifndef NRSFM_CORE_MODEL_SHAPE_LAYOUTS_H_
#define NRSFM_CORE_MODEL_SHAPE_LAYOUTS_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/model/status.h"

namespace nrsfm {

// Fails when the matrix is empty or its rows are not a multiple of 3.
Status FramesFromInterleaved(const Eigen::MatrixXd& points,
                             const std::string& name,
                             std::vector<Eigen::Matrix3Xd>* frames);
Status FramesFromBlockLayout(const Eigen::MatrixXd& points,
                             const std::string& name,
                             std::vector<Eigen::Matrix3Xd>* frames);
// Fails when there is no slice, a slice is empty, a slice's row count is not
// 3 or the slices differ in size.
Status FramesFromArray3(const std::vector<Eigen::MatrixXd>& slices,
                        const std::string& name,
                        std::vector<Eigen::Matrix3Xd>* frames);

// The 2F × P orthographic measurement matrix of the frames: rows 2t and
// 2t+1 are the x and y rows of frame t (z dropped). All frames must have the
// same number of points (CHECKed).
Eigen::MatrixXd OrthographicW(const std::vector<Eigen::Matrix3Xd>& frames);

}  // namespace nrsfm

#endif  // NRSFM_CORE_MODEL_SHAPE_LAYOUTS_H_
