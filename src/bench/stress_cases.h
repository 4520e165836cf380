#pragma once
// The stress suite's cases (bench/stress.h), internal to src/bench/: each builds its geometry in
// code, runs the pipeline on the context's backend (or the solver alone) and returns its row,
// the error measured against the case's oracle. runStressSuite chooses the sizes.
#include <memory>
#include <string>

#include "backend/backend.h"
#include "bench/stress.h"
#include "geometry/mesh.h"
#include "geometry/patch_mesh.h"
#include "radiosity/transport.h"

namespace daisy::stress {

struct Context {
    const StressSettings& settings;
    std::string backendName = "-";  // "-" for solver-only cases
    std::shared_ptr<Backend> backend;  // shared by the cases' sessions (one Vulkan device)
};

struct Built {
    PatchMesh mesh;
    std::shared_ptr<const Transport> f;  // the transport built: F
    std::string error;  // non-empty when the pipeline refused the input
};

// The mesh through the session, as every front end runs it: patches at maxEdge (0 = the
// triangles), then F on the context's backend without the disk cache.
Built buildAll(const Context& context, const TriangleMesh& triangles, double maxEdge = 0);

// A 1 m room with a solid box inside, every coordinate scaled by `scale` metres.
TriangleMesh scaledRoom(double scale);

// The cases; `n` (or `k`) is the subdivision of each face into n x n x 2 triangles.
StressRow closedBoxRowSums(const Context& context, std::string name, Vec3d size, int n);
StressRow furnace(const Context& context, double rho, int n);
StressRow furnaceExact(const Context& context, double rho);
StressRow scaleInvariance(const Context& context, double scale, const Built& unit);
StressRow sliverStrips(const Context& context);
StressRow nearlyCoincident(const Context& context, double gap, int n);
StressRow sharedEdge(const Context& context, double degrees, int n);
StressRow coplanar(const Context& context, int n);
StressRow fluorescentChain(const Context& context, int n);
StressRow longRow(const Context& context, int k);

}  // namespace daisy::stress
