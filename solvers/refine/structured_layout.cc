#include "solvers/refine/structured_layout.h"

#include <glog/logging.h>

#include <algorithm>
#include <map>
#include <typeindex>
#include <typeinfo>
#include <unordered_map>
#include <utility>

namespace nrsfm {
namespace structured {

namespace {

// Sets s->grids and the residuals' in_grid: the residual blocks with a
// bilinear form are grouped by their cost function's class and the pattern
// of their rows (K, the mask, and the signs of the weights blocks): one
// term. Each group whose blocks are every row in every column, each once, with
// its weights blocks free and in frame groups, its basis blocks eliminated
// and one scale per column, becomes a grid. Other groups are handled block
// by block.
void FindGrids(StructuredBlocks* s) {
  struct Candidate {
    BilinearGrid grid;
    std::map<std::vector<std::pair<int, double>>, int> row_index, column_index;
    std::vector<int> members;
    std::vector<std::pair<int, int>> cells;  // (row, column)
    bool valid = true;
  };
  // Keyed by the cost function's class too: two terms whose rows have the
  // same form are never summed as one grid.
  std::map<std::pair<std::type_index, std::vector<double>>, Candidate>
      candidates;
  // The last residual's cost function, its form and candidate: the blocks
  // of one term usually share one cost function (problems/extra_terms.cc),
  // so each form is asked for once per run of blocks.
  const ceres::CostFunction* last_cost = nullptr;
  bool last_has_form = false;
  BilinearForm form;
  Candidate* candidate = nullptr;
  std::vector<std::pair<int, double>> row, column, last_row;
  int last_row_index = -1;
  for (std::size_t i = 0; i < s->residuals.size(); ++i) {
    const Residual& r = s->residuals[i];
    if (r.cost != last_cost) {
      last_cost = r.cost;
      last_row.clear();
      last_row_index = -1;
      // The form is the cost function's (r.product is also null for a
      // residual whose blocks have a manifold: tested per residual below).
      const auto* product = dynamic_cast<const JacobianProduct*>(r.cost);
      last_has_form = product != nullptr && product->GetBilinearForm(&form);
      if (last_has_form) {
        CHECK_EQ(form.signs.size(), r.slot_block.size());
        CHECK_EQ(form.is_weights.size(), r.slot_block.size());
        CHECK(form.mask.empty() ||
              static_cast<int>(form.mask.size()) == form.num_bases);
        std::vector<double> mask = form.mask;
        if (mask.empty()) mask.assign(form.num_bases, 1.0);
        // The columns keep their own points and signs (a smoothness
        // stencil's count and weights vary from point to point), so only
        // the rows' form is the pattern.
        std::vector<double> pattern = {static_cast<double>(form.num_bases)};
        pattern.insert(pattern.end(), mask.begin(), mask.end());
        for (std::size_t k = 0; k < form.signs.size(); ++k) {
          if (form.is_weights[k]) pattern.push_back(form.signs[k]);
        }
        candidate = &candidates[{std::type_index(typeid(*r.cost)), pattern}];
        if (candidate->members.empty()) {
          candidate->grid.num_bases = form.num_bases;
          candidate->grid.mask = Eigen::Map<const Eigen::VectorXd>(
              mask.data(), static_cast<Eigen::Index>(mask.size()));
        }
      }
    }
    if (!last_has_form || r.product == nullptr) continue;
    Candidate& c = *candidate;
    if (!c.valid) continue;
    row.clear();
    column.clear();
    for (std::size_t k = 0; k < r.slot_block.size() && c.valid; ++k) {
      const int block = r.slot_block[k];
      if (block < 0) {
        c.valid = false;  // a constant block: not the grid's form
        break;
      }
      const Block& b = s->blocks[block];
      if (form.is_weights[k]) {
        c.valid = !b.eliminated && b.group >= 0 && b.manifold == nullptr &&
                  b.size == form.num_bases;
        row.emplace_back(block, form.signs[k]);
      } else {
        c.valid = b.eliminated && b.manifold == nullptr &&
                  b.size == 3 * form.num_bases;
        column.emplace_back(block, form.signs[k]);
      }
    }
    if (!c.valid) continue;
    // Consecutive blocks of a term often share their row (one frame's
    // points).
    if (last_row_index < 0 || row != last_row) {
      auto q = c.row_index.find(row);
      if (q == c.row_index.end()) {
        q = c.row_index.emplace(row, static_cast<int>(c.grid.rows.size()))
                .first;
        std::vector<BilinearGrid::Term> terms;
        for (const auto& [block, sign] : row) terms.push_back({block, sign});
        c.grid.rows.push_back(std::move(terms));
      }
      last_row = row;
      last_row_index = q->second;
    }
    auto e = c.column_index.find(column);
    if (e == c.column_index.end()) {
      e = c.column_index
              .emplace(column, static_cast<int>(c.grid.columns.size()))
              .first;
      BilinearGrid::Column added;
      for (const auto& [block, sign] : column)
        added.points.push_back({block, sign});
      added.scale = form.scale;
      c.grid.columns.push_back(std::move(added));
    } else if (c.grid.columns[e->second].scale != form.scale) {
      c.valid = false;
      continue;
    }
    c.members.push_back(static_cast<int>(i));
    c.cells.emplace_back(last_row_index, e->second);
  }
  for (auto& [pattern, c] : candidates) {
    std::sort(c.cells.begin(), c.cells.end());
    if (!c.valid || c.members.empty() ||
        std::adjacent_find(c.cells.begin(), c.cells.end()) != c.cells.end() ||
        c.cells.size() != c.grid.rows.size() * c.grid.columns.size()) {
      continue;  // not a full grid: its residuals are handled one by one
    }
    for (int i : c.members) s->residuals[i].in_grid = true;
    s->grids.push_back(std::move(c.grid));
  }
  if (s->grids.empty()) return;
  for (std::size_t i = 0; i < s->residuals.size(); ++i) {
    if (!s->residuals[i].in_grid) s->not_in_grid.push_back(static_cast<int>(i));
  }
}

}  // namespace

bool LayOutBlocks(const StructuredLayout& layout, ceres::Problem* problem,
                  StructuredBlocks* s, std::string* error) {
  *s = StructuredBlocks();
  std::unordered_map<const double*, int> index;
  auto add = [&](double* values, bool eliminated, int group) {
    if (!problem->HasParameterBlock(values) ||
        problem->IsParameterBlockConstant(values) || index.count(values)) {
      return;
    }
    Block b;
    b.values = values;
    b.ambient = problem->ParameterBlockSize(values);
    b.manifold =
        problem->HasManifold(values) ? problem->GetManifold(values) : nullptr;
    b.size = b.manifold != nullptr ? b.manifold->TangentSize() : b.ambient;
    b.eliminated = eliminated;
    b.group = group;
    int& counter = eliminated ? s->num_eliminated : s->num_reduced;
    b.offset = counter;
    counter += b.size;
    index[values] = static_cast<int>(s->blocks.size());
    if (eliminated)
      s->eliminated_blocks.push_back(static_cast<int>(s->blocks.size()));
    s->blocks.push_back(b);
  };
  s->group_offset.push_back(0);
  for (std::size_t g = 0; g < layout.groups.size(); ++g) {
    for (double* values : layout.groups[g])
      add(values, false, static_cast<int>(g));
    s->group_offset.push_back(s->num_reduced);
  }
  s->num_group_columns = s->num_reduced;
  for (double* values : layout.globals) add(values, false, -1);
  for (double* values : layout.eliminated) add(values, true, -1);
  const int num_groups = static_cast<int>(layout.groups.size());

  // `index` gets the constant blocks too (-1) as they are met, so that each
  // is asked of the problem once; `last` holds per slot the last block met.
  std::vector<std::pair<const double*, int>> last;
  std::vector<ceres::ResidualBlockId> ids;
  problem->GetResidualBlocks(&ids);
  s->residuals.reserve(ids.size());
  // Each residual's lists are formed here, then appended to the pools; the
  // spans are set once the pools have stopped growing.
  std::vector<double*> parameters;
  std::vector<int> slot_block, slot_jcol;
  std::vector<Segment> reduced;
  std::vector<Coupled> coupled;
  struct Starts {
    std::size_t parameters, slots, reduced, coupled;
  };
  std::vector<Starts> starts;
  starts.reserve(ids.size());
  for (ceres::ResidualBlockId id : ids) {
    Residual r;
    r.cost = problem->GetCostFunctionForResidualBlock(id);
    r.loss = problem->GetLossFunctionForResidualBlock(id);
    const BasisJacobianFactor* basis_factor =
        r.loss == nullptr ? dynamic_cast<const BasisJacobianFactor*>(r.cost)
                          : nullptr;
    r.m = r.cost->num_residuals();
    r.row = s->num_rows;
    s->num_rows += r.m;
    problem->GetParameterBlocksForResidualBlock(id, &parameters);
    slot_block.clear();
    slot_jcol.clear();
    reduced.clear();
    coupled.clear();
    if (last.size() < parameters.size())
      last.resize(parameters.size(), {nullptr, -1});
    for (std::size_t k = 0; k < parameters.size(); ++k) {
      double* values = parameters[k];
      // Consecutive residual blocks often share a block in the same slot.
      if (last[k].first != values) {
        const auto it = index.find(values);
        if (it != index.end()) {
          last[k] = {values, it->second};
        } else if (problem->IsParameterBlockConstant(values)) {
          index.emplace(values, -1);
          last[k] = {values, -1};
        } else {
          *error = "a free parameter block of the problem is not in the layout";
          return false;
        }
      }
      const int block = last[k].second;
      slot_block.push_back(block);
      slot_jcol.push_back(r.width);
      if (block < 0) continue;
      const Block& b = s->blocks[block];
      if (b.eliminated) {
        if (r.eliminated >= 0 || !coupled.empty()) {
          // A second eliminated block: both become `coupled`.
          if (r.basis_factor != nullptr) {
            *error =
                "a reprojection residual block holds two eliminated blocks";
            return false;
          }
          if (r.eliminated >= 0) {
            coupled.push_back({r.eliminated, r.eliminated_jcol});
            r.eliminated = -1;
          }
          coupled.push_back({block, r.width});
          r.width += b.size;
          continue;
        }
        r.eliminated = block;
        r.eliminated_jcol = r.width;
        if (basis_factor != nullptr && b.manifold == nullptr &&
            slot_block.size() == BasisJacobianFactor::kBasisSlot + 1) {
          // The basis block's columns are formed from A and l, not stored.
          r.basis_factor = basis_factor;
          r.num_bases = basis_factor->num_bases();
          r.weights = parameters[BasisJacobianFactor::kWeightsSlot];
          slot_jcol.back() = -1;
          continue;
        }
      } else {
        // Merge with the previous segment when the columns continue it
        // within the same group.
        if (!reduced.empty() && b.group >= 0 &&
            reduced.back().group == b.group &&
            reduced.back().col + reduced.back().width == b.offset &&
            reduced.back().jcol + reduced.back().width == r.width) {
          reduced.back().width += b.size;
        } else {
          reduced.push_back({b.offset, b.size, r.width, b.group});
        }
      }
      r.width += b.size;
    }
    int lo = num_groups, hi = -1;
    for (const Segment& segment : reduced) {
      if (segment.group < 0) continue;
      lo = std::min(lo, segment.group);
      hi = std::max(hi, segment.group);
    }
    if (hi >= 0) s->band = std::max(s->band, hi - lo);
    if (r.loss == nullptr) {
      r.product = dynamic_cast<const JacobianProduct*>(r.cost);
      for (int block : slot_block) {
        if (block >= 0 && s->blocks[block].manifold != nullptr)
          r.product = nullptr;
      }
    }
    if (r.product != nullptr && r.product->ProvidesGram() && coupled.empty()) {
      r.gram = true;
    }
    starts.push_back({s->parameter_pool.size(), s->slot_pool.size(),
                      s->segment_pool.size(), s->coupled_pool.size()});
    s->parameter_pool.insert(s->parameter_pool.end(), parameters.begin(),
                             parameters.end());
    s->slot_pool.insert(s->slot_pool.end(), slot_block.begin(),
                        slot_block.end());
    s->slot_pool.insert(s->slot_pool.end(), slot_jcol.begin(), slot_jcol.end());
    s->segment_pool.insert(s->segment_pool.end(), reduced.begin(),
                           reduced.end());
    s->coupled_pool.insert(s->coupled_pool.end(), coupled.begin(),
                           coupled.end());
    s->residuals.push_back(r);
  }
  for (std::size_t i = 0; i < s->residuals.size(); ++i) {
    Residual& r = s->residuals[i];
    const Starts& at = starts[i];
    const std::size_t n = (i + 1 < starts.size() ? starts[i + 1].parameters
                                                 : s->parameter_pool.size()) -
                          at.parameters;
    r.parameters = Span<double*>(s->parameter_pool.data() + at.parameters, n);
    r.slot_block = Span<int>(s->slot_pool.data() + at.slots, n);
    r.slot_jcol = Span<int>(s->slot_pool.data() + at.slots + n, n);
    const std::size_t num_reduced =
        (i + 1 < starts.size() ? starts[i + 1].reduced
                               : s->segment_pool.size()) -
        at.reduced;
    r.reduced = Span<Segment>(s->segment_pool.data() + at.reduced, num_reduced);
    const std::size_t num_coupled =
        (i + 1 < starts.size() ? starts[i + 1].coupled
                               : s->coupled_pool.size()) -
        at.coupled;
    r.coupled = Span<Coupled>(s->coupled_pool.data() + at.coupled, num_coupled);
  }
  FindGrids(s);

  s->group_refs.assign(num_groups, {});
  s->eliminated_refs.assign(s->eliminated_blocks.size(), {});
  std::vector<int> eliminated_position(s->blocks.size(), -1);
  for (std::size_t k = 0; k < s->eliminated_blocks.size(); ++k) {
    eliminated_position[s->eliminated_blocks[k]] = k;
  }
  for (std::size_t i = 0; i < s->residuals.size(); ++i) {
    const Residual& r = s->residuals[i];
    if (r.in_grid) continue;  // a grid's part is added at once
    bool with_shared = false;
    for (std::size_t k = 0; k < r.reduced.size(); ++k) {
      if (r.reduced[k].group >= 0) {
        s->group_refs[r.reduced[k].group].push_back(
            {static_cast<int>(i), static_cast<int>(k)});
      } else {
        with_shared = true;
      }
    }
    if (with_shared) s->residuals_with_shared.push_back(static_cast<int>(i));
    if (!r.coupled.empty())
      s->coupling_residuals.push_back(static_cast<int>(i));
    if (r.eliminated >= 0) {
      s->eliminated_refs[eliminated_position[r.eliminated]].push_back(
          {static_cast<int>(i), -1});
    }
  }
  return true;
}

}  // namespace structured
}  // namespace nrsfm
