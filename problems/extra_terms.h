// The residual terms beyond the data term, described once: the table of
// ExtraTerms() (problems/extra_terms.cc) is what ProblemOptions::Check(), the
// problem builder (AddExtraTerms), the nrsfm tool's flags and result.json
// read. Each term has one name, which is also its flag and its key in
// result.json, and a weight λ ≥ 0 in ProblemOptions::term_weights (0, the
// default, leaves it out); λ multiplies the term's cost, so its functor
// applies √λ. The terms, their equations and their units are in
// docs/problem.md, which also shows how to add one (a functor header, one
// row of the table and the term's own test; nothing else).
#ifndef NRSFM_PROBLEMS_EXTRA_TERMS_H_
#define NRSFM_PROBLEMS_EXTRA_TERMS_H_

#include <string>
#include <vector>

#include "core/model/status.h"
#include "problems/problem_builder.h"
#include "problems/problem_options.h"

namespace nrsfm {

// The names of the terms (ExtraTerm::name, keys of
// ProblemOptions::term_weights, the nrsfm tool's flags), for code that sets a
// weight.
inline constexpr char kSmoothnessTerm[] = "smoothness";
inline constexpr char kRigidityTerm[] = "rigidity";
inline constexpr char kTemporalTerm[] = "temporal";
inline constexpr char kTemporalRotationsTerm[] = "temporal_rotations";
inline constexpr char kTemporalShapeTerm[] = "temporal_shape";
inline constexpr char kRotationAccelerationTerm[] = "rotation_acceleration";
inline constexpr char kDeformationTerm[] = "deformation";

struct ExtraTerm {
  // Adds the residual blocks of the term with weight `weight` > 0 to the
  // builder's problem and returns how many; errors (e.g. data the term cannot
  // use) name the reason.
  using AddFunction = Status (*)(double weight, const ProblemOptions& options,
                                 ProblemBuilder* builder, int* num_blocks);

  // Key of ProblemOptions::term_weights, the nrsfm tool's flag (--name λ)
  // and the key in result.json's options and term_weights.
  const char* name;
  const char* units;  // of λ
  // Whether λ is in (input units)² (per rad² or per weight²): the term's
  // residual has no input units while the data term's does, so measuring
  // the input in other units changes the λ that means the same balance.
  bool weight_in_squared_input_units;
  const char* meaning;  // one line: the residual and when to use the term
  int min_cameras;      // the term needs M ≥ min_cameras
  AddFunction add;

  // The one check of min_cameras (AddExtraTerms, the nrsfm tool): an error
  // "needs data from M >= <min_cameras> synchronised cameras, got M = <M>"
  // when num_cameras is too few.
  Status CheckCameras(int num_cameras) const;
};

// Every extra term, in the order AddExtraTerms adds them.
const std::vector<ExtraTerm>& ExtraTerms();
// The term called `name`, or null.
const ExtraTerm* FindExtraTerm(const std::string& name);

// Adds the residual blocks of every term with a non-zero weight, in table
// order, after builder->AddReprojectionTerms(options), and applies the
// constant flags of `options` to the blocks they added (the rig blocks are
// free unless constant_rig). `num_blocks` (optional) receives the residual
// blocks added per term, aligned with ExtraTerms(). Errors on invalid
// options, on a term whose min_cameras exceeds M, and when a term cannot be
// added (e.g. a smoothness reference view that cannot be triangulated); the
// problem is then incomplete and must not be solved.
Status AddExtraTerms(const ProblemOptions& options, ProblemBuilder* builder,
                     std::vector<int>* num_blocks = nullptr);

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_EXTRA_TERMS_H_
