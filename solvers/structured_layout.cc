#include "solvers/structured_layout.h"

#include <algorithm>
#include <map>
#include <unordered_map>
#include <utility>

#include "problems/smoothness_error.h"

namespace nrsfm {
namespace structured {

namespace {

// Sets s->smoothness and the residuals' in_grid when the smoothness
// residuals (weights free and reduced, both basis blocks eliminated, no
// loss) are every edge in every frame of one set, each pair once.
void FindSmoothnessGrid(StructuredBlocks* s) {
  std::map<std::pair<int, int>, int> edge_index;
  std::map<int, int> frame_index;
  SmoothnessGrid grid;
  std::vector<int> members;
  std::vector<std::pair<int, int>> cells;  // (edge, frame)
  for (std::size_t i = 0; i < s->residuals.size(); ++i) {
    const Residual& r = s->residuals[i];
    const auto* cost = dynamic_cast<const SmoothnessError*>(r.cost);
    if (cost == nullptr) continue;
    const int w = r.slot_block.size() == 3 ? r.slot_block[0] : -1;
    if (r.loss != nullptr || w < 0 || s->blocks[w].eliminated ||
        s->blocks[w].group < 0 || s->blocks[w].manifold != nullptr ||
        r.coupled.size() != 2 || r.slot_block[1] != r.coupled[0].block ||
        r.slot_block[2] != r.coupled[1].block ||
        (grid.num_bases != 0 && grid.num_bases != cost->num_bases())) {
      return;
    }
    grid.num_bases = cost->num_bases();
    const std::pair<int, int> key(r.slot_block[1], r.slot_block[2]);
    auto edge = edge_index.find(key);
    if (edge == edge_index.end()) {
      edge = edge_index.emplace(key, static_cast<int>(grid.edges.size())).first;
      grid.edges.push_back({key.first, key.second, cost->scale()});
    } else if (grid.edges[edge->second].scale != cost->scale()) {
      return;
    }
    auto frame = frame_index.find(w);
    if (frame == frame_index.end()) {
      frame =
          frame_index.emplace(w, static_cast<int>(grid.weights.size())).first;
      grid.weights.push_back(w);
    }
    members.push_back(static_cast<int>(i));
    cells.emplace_back(edge->second, frame->second);
  }
  std::sort(cells.begin(), cells.end());
  if (members.empty() ||
      std::adjacent_find(cells.begin(), cells.end()) != cells.end() ||
      cells.size() != grid.edges.size() * grid.weights.size()) {
    return;  // not a full grid: the residuals are handled one by one
  }
  for (int i : members) s->residuals[i].in_grid = true;
  for (std::size_t i = 0; i < s->residuals.size(); ++i) {
    if (!s->residuals[i].in_grid) s->not_in_grid.push_back(static_cast<int>(i));
  }
  s->smoothness = std::move(grid);
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

  std::vector<ceres::ResidualBlockId> ids;
  problem->GetResidualBlocks(&ids);
  s->residuals.reserve(ids.size());
  std::size_t jac = 0, factor = 0;
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
    problem->GetParameterBlocksForResidualBlock(id, &r.parameters);
    for (double* values : r.parameters) {
      int block = -1;
      if (!problem->IsParameterBlockConstant(values)) {
        const auto it = index.find(values);
        if (it == index.end()) {
          *error = "a free parameter block of the problem is not in the layout";
          return false;
        }
        block = it->second;
      }
      r.slot_block.push_back(block);
      r.slot_jcol.push_back(r.width);
      if (block < 0) continue;
      const Block& b = s->blocks[block];
      if (b.eliminated) {
        if (r.eliminated >= 0 || !r.coupled.empty()) {
          // A second eliminated block: both become `coupled`.
          if (r.basis_factor != nullptr) {
            *error =
                "a reprojection residual block holds two eliminated blocks";
            return false;
          }
          if (r.eliminated >= 0) {
            r.coupled.push_back({r.eliminated, r.eliminated_jcol});
            r.eliminated = -1;
          }
          r.coupled.push_back({block, r.width});
          r.width += b.size;
          continue;
        }
        r.eliminated = block;
        r.eliminated_jcol = r.width;
        if (basis_factor != nullptr && b.manifold == nullptr &&
            r.slot_block.size() == BasisJacobianFactor::kBasisSlot + 1) {
          // The basis block's columns are formed from A and l, not stored.
          r.basis_factor = basis_factor;
          r.num_bases = basis_factor->num_bases();
          r.weights = r.parameters[BasisJacobianFactor::kWeightsSlot];
          r.factor = factor;
          factor += 6;
          r.slot_jcol.back() = -1;
          continue;
        }
      } else {
        // Merge with the previous segment when the columns continue it
        // within the same group.
        if (!r.reduced.empty() && b.group >= 0 &&
            r.reduced.back().group == b.group &&
            r.reduced.back().col + r.reduced.back().width == b.offset &&
            r.reduced.back().jcol + r.reduced.back().width == r.width) {
          r.reduced.back().width += b.size;
        } else {
          r.reduced.push_back({b.offset, b.size, r.width, b.group});
        }
      }
      r.width += b.size;
    }
    r.jac = jac;
    jac += static_cast<std::size_t>(r.m) * r.width;
    int lo = num_groups, hi = -1;
    for (const Segment& segment : r.reduced) {
      if (segment.group < 0) continue;
      lo = std::min(lo, segment.group);
      hi = std::max(hi, segment.group);
    }
    if (hi >= 0) s->band = std::max(s->band, hi - lo);
    if (r.loss == nullptr) {
      r.product = dynamic_cast<const JacobianProduct*>(r.cost);
      for (int block : r.slot_block) {
        if (block >= 0 && s->blocks[block].manifold != nullptr)
          r.product = nullptr;
      }
    }
    if (r.product != nullptr && r.product->ProvidesGram() &&
        r.coupled.empty()) {
      r.gram = true;
      jac -= static_cast<std::size_t>(r.m) * r.width;  // nothing stored
    }
    s->residuals.push_back(std::move(r));
  }
  s->jacobian_size = jac;
  s->factors_size = factor;
  FindSmoothnessGrid(s);

  s->group_refs.assign(num_groups, {});
  s->eliminated_refs.assign(s->eliminated_blocks.size(), {});
  std::vector<int> eliminated_position(s->blocks.size(), -1);
  for (std::size_t k = 0; k < s->eliminated_blocks.size(); ++k) {
    eliminated_position[s->eliminated_blocks[k]] = k;
  }
  for (std::size_t i = 0; i < s->residuals.size(); ++i) {
    const Residual& r = s->residuals[i];
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
