#pragma once
// Sum of every force acting on the fabric.

#include <array>
#include <cstdint>
#include <vector>

#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/force_sink.h"

namespace haptex::textile {

/// Adds tensile, shear, bending, damping, drag, gravity and applied loads into `sink` (which the
/// caller zeroes; the blocks triangles touch may instead start from `sink->system_base`). One
/// pass per element: each system block is written once. Never allocates.
void AccumulateForces(const FabricModel& model, const FabricState& state, ForceSink* sink);

/// Adds the state-independent Jacobian blocks (bending with its damping, linear drag) into
/// `sink->system` with the sink's scales; for callers that cache them between steps and set
/// `sink->constant_jacobians_added`. Never allocates.
void AddConstantJacobians(const FabricModel& model, ForceSink* sink);

namespace internal {
/// Builds of the force kernels (one source): portable; AVX2; and for the triangle kernel AVX2 on
/// AVX-512VL's 32 registers (fewer spills), the bending kernel's AVX2 there. All give the same bits.
enum class ForceKernels { kPortable, kAvx2, kAvx2On32Registers };
/// The fastest build this CPU runs.
ForceKernels BestForceKernels();
/// AccumulateForces with the given build (only one the CPU has): tests compare their bits.
void AccumulateForces(const FabricModel& model, const FabricState& state, ForceKernels kernels, ForceSink* sink);
/// FabricModel::triangle_first_blocks for triangles with these block slots (num_blocks slots):
/// per triangle, 1 at the blocks k*3+l whose addition is the first to their slot in the
/// triangle kernel's order, else 0.
std::vector<std::array<std::uint8_t, 9>> TriangleFirstBlocks(const std::vector<std::array<int, 9>>& triangle_slots,
                                                             int num_blocks);
}  // namespace internal

}  // namespace haptex::textile
