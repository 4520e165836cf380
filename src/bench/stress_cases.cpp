// The stress suite's cases (stress_cases.h). Every case builds its geometry in code, runs the
// real pipeline and measures one error against a closed form (Howell, "A Catalog of Radiation
// Heat Transfer Configuration Factors", 3rd ed., cases B-3, C-11, C-14), a double-precision
// quadrature of the exact point-to-polygon factor (both in verify/closed_forms.h), or a
// conservation law. Over 400 lines because each case is short but there are many.
#include "bench/stress_cases.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>

#include "core/strings.h"
#include "core/timer.h"
#include "geometry/patch_mesh.h"
#include "pipeline/session.h"
#include "radiosity/energy.h"
#include "radiosity/form_factors.h"
#include "radiosity/matrix_transport.h"
#include "radiosity/radiosity_system.h"
#include "radiosity/solver.h"
#include "spectral/fluorescence.h"
#include "spectral/wavelength_set.h"
#include "spectral/wavelength_spec.h"
#include "verify/closed_forms.h"
#include "verify/scenes.h"

namespace daisy::stress {
namespace {

using verify::addGrid;
using verify::addRoom;
using verify::groupFactor;
using verify::hingedSquares;
using verify::parallelRectangles;
using verify::perpendicularRectangles;
using verify::smallSquareToPlane;
constexpr double kPi = std::numbers::pi;

bool allFinite(std::span<const double> values) {
    return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

// A system over `mesh` with m unit-width samples at `wavelengthsNm`, every patch on operator 0.
RadiositySystem systemFor(const std::vector<double>& areas, std::vector<double> wavelengthsNm,
                          std::vector<double> binWidthsNm, std::vector<MaterialOperator> ops) {
    RadiositySystem system;
    system.patchCount = static_cast<uint32_t>(areas.size());
    system.wavelengthCount = wavelengthsNm.size();
    system.wavelengthsNm = std::move(wavelengthsNm);
    system.binWidthsNm = std::move(binWidthsNm);
    system.emission.assign(areas.size() * system.wavelengthCount, 0);
    system.areas = areas;
    system.patchOperator.assign(areas.size(), 0);
    system.operators = std::move(ops);
    return system;
}

MaterialOperator greyOperator(double rho) {
    MaterialOperator op;
    op.matrix.size = 1;
    op.matrix.values = {rho};
    finishOperator(op, {1.0});
    return op;
}

std::string solveStatus(const SolverResult& solved) {
    if (solved.converged)
        return concat("converged (", solved.iterations, " it, residual ",
                      formatNumber(solved.residual, 2), ")");
    return concat("NOT converged: ", solved.warning);
}

StressRow rowFor(const Context& context, std::string name, std::string oracle) {
    StressRow row;
    row.name = std::move(name);
    row.backend = context.backendName;
    row.oracle = std::move(oracle);
    row.status = "n/a";
    return row;
}

bool failed(StressRow& row, const std::string& message) {
    row.status = concat("pipeline refused: ", message);
    row.pass = false;
    return true;
}

}  // namespace

// No disk cache: every case measures its own build. The cases bring their own radiosity systems
// (exact operators, unit bins), so the session's default materials only make the scene complete.
Built buildAll(const Context& context, const TriangleMesh& triangles, double maxEdge) {
    Built built;
    Scene scene;
    scene.path = "stress";
    scene.mesh = triangles;
    uint32_t materials = 1;
    for (uint32_t material : triangles.materials)
        materials = std::max(materials, material + 1);
    for (uint32_t k = 0; k < materials; ++k) {
        Material material;
        material.name = concat("m", k);
        material.origin = concat("stress: material ", k);
        scene.materials.push_back(material);
    }
    SessionSettings settings;
    settings.backend = context.backendName;
    settings.backendInstance = context.backend;
    settings.subdivideMaxEdge = maxEdge;
    settings.formFactors.threads = context.settings.threads;
    settings.formFactors.progress = false;
    settings.wavelengths = *parseWavelengthSpec("550");
    settings.wavelengthsText = "550";
    settings.logStages = false;
    auto session = Session::fromScene(std::move(scene), std::move(settings));
    if (!session) return built.error = session.error().message, built;
    if (auto f = session->buildFormFactors(); !f) return built.error = f.error().message, built;
    built.mesh = session->patches();
    built.f = session->sharedTransport();
    return built;
}

// Closed box: every row of F sums to 1 (DESIGN.md section 2).
StressRow closedBoxRowSums(const Context& context, std::string name, Vec3d size, int n) {
    StressRow row = rowFor(context, std::move(name), "row sums = 1 (closed enclosure)");
    TriangleMesh mesh;
    addRoom(mesh, {0, 0, 0}, size, n);
    const Built b = buildAll(context, mesh);
    if (!b.error.empty() && failed(row, b.error)) return row;
    const std::span<const double> sums = b.f->rowSums();
    row.patches = b.mesh.patchCount();
    row.finite = b.f->checkStructure().empty() && allFinite(sums);
    for (double s : sums)
        row.error = std::max(row.error, std::abs(s - 1));
    // DAISY_FF_REL_TOL (3e-4) per pair, errors of either sign: 1e-3 on a row.
    row.tolerance = 1e-3;
    row.pass = row.finite && row.error <= row.tolerance;
    return row;
}

// Furnace: a closed room, uniform rho, unit emission everywhere. With exact F, B = E / (1 - rho);
// with F's row sums in [smin, smax], every B_i lies in [E / (1 - rho smin), E / (1 - rho smax)]
// (F >= 0: the Neumann series is monotone). Error: max |B_i (1 - rho) / E - 1|; tolerance: the
// bracket's widest end plus the solver's share 2 tau / (1 - rho).
StressRow furnace(const Context& context, double rho, int n) {
    StressRow row = rowFor(context, concat("furnace rho=", formatNumber(rho)),
                           "B = E/(1-rho), bracket from row sums");
    TriangleMesh mesh;
    addRoom(mesh, {0, 0, 0}, {1, 1, 1}, n);
    const Built b = buildAll(context, mesh);
    if (!b.error.empty() && failed(row, b.error)) return row;
    row.patches = b.mesh.patchCount();
    const std::span<const double> sums = b.f->rowSums();
    const auto [smin, smax] = std::minmax_element(sums.begin(), sums.end());
    RadiositySystem system = systemFor(b.mesh.areas, {550}, {1}, {greyOperator(rho)});
    std::fill(system.emission.begin(), system.emission.end(), 1.0);
    SolverSettings settings;
    settings.tolerance = 1e-9;
    settings.maxIterations = 100000;
    settings.threads = context.settings.threads;
    auto solved = b.f->solve(system, settings);
    if (!solved) {
        row.status = concat("diagnosed: ", solved.error().message);
        row.pass = rho * *smax >= 1;  // refusing is right only when F amplifies
        return row;
    }
    row.finite = allFinite(solved->radiosity);
    const double ideal = 1 / (1 - rho);
    for (double bi : solved->radiosity)
        row.error = std::max(row.error, std::abs(bi / ideal - 1));
    const double lower = (1 - rho) / (1 - rho * *smin) - 1;
    const double upper = rho * *smax < 1 ? (1 - rho) / (1 - rho * *smax) - 1 : INFINITY;
    row.tolerance = std::max(std::abs(lower), std::abs(upper)) + 2 * settings.tolerance / (1 - rho);
    row.status = concat(solveStatus(*solved), ", rowsum ", formatNumber(*smin, 7), "..",
                        formatNumber(*smax, 7), ", ", formatNumber(solved->seconds, 3), " s");
    row.pass = row.finite && solved->converged && row.error <= row.tolerance;
    return row;
}

// The solver alone: n = 65 patches, F_ij = 1/64 (exact in float), rows summing to exactly 1.
StressRow furnaceExact(const Context& context, double rho) {
    StressRow row =
        rowFor(context, concat("furnace exact F rho=", formatNumber(rho)), "B = E/(1-rho) exactly");
    const uint32_t n = 65;
    const auto f =
        denseTransport(n, [](uint32_t i, uint32_t j) { return i == j ? 0.0f : 1.0f / 64; });
    RadiositySystem system =
        systemFor(std::vector<double>(n, 1.0), {550}, {1}, {greyOperator(rho)});
    std::fill(system.emission.begin(), system.emission.end(), 1.0);
    SolverSettings settings;
    settings.tolerance = 1e-9;
    settings.maxIterations = 100000;
    settings.threads = context.settings.threads;
    row.patches = n;
    auto solved = f->solve(system, settings);
    if (!solved) return row.status = concat("diagnosed: ", solved.error().message), row;
    row.finite = allFinite(solved->radiosity);
    for (double bi : solved->radiosity)
        row.error = std::max(row.error, std::abs(bi * (1 - rho) - 1));
    row.tolerance = 2 * settings.tolerance / (1 - rho);
    row.status = solveStatus(*solved);
    row.pass = row.finite && solved->converged && row.error <= row.tolerance;
    return row;
}

// A room with a solid box inside, scaled by `scale` metres: F is dimensionless, so every entry
// must match the 1 m result (shafts, ray margins and plane tolerances must be relative).
TriangleMesh scaledRoom(double scale) {
    TriangleMesh mesh;
    addRoom(mesh, Vec3d{0.3, -0.2, 0.5} * scale, Vec3d{1, 1, 1} * scale, 3);
    verify::addSolidBox(mesh, Vec3d{0.65, 0.15, 0.85} * scale, Vec3d{0.3, 0.3, 0.3} * scale);
    return mesh;
}

StressRow scaleInvariance(const Context& context, double scale, const Built& unit) {
    StressRow row = rowFor(context, concat("scale ", formatNumber(scale), " m"),
                           "max |F - F(1 m)| (F dimensionless)");
    const Built b = buildAll(context, scaledRoom(scale));
    if (!b.error.empty() && failed(row, b.error)) return row;
    row.patches = b.mesh.patchCount();
    row.finite = b.f->checkStructure().empty();
    const auto compared = b.f->compare(*unit.f, {});
    if (!compared && failed(row, compared.error().message)) return row;
    const EntryDifference worst = compared->maxAbsolute;
    row.error = worst.absolute;
    // Float rounding of the scaled coordinates moves each kernel by ~1e-6 relative.
    row.tolerance = 1e-5;
    if (row.error > 0)
        row.status = concat("worst F(", worst.row, ",", worst.column,
                            ") = ", formatNumber(worst.a, 6), " vs ", formatNumber(worst.b, 6));
    row.pass = row.finite && row.error <= row.tolerance;
    return row;
}

// Two 1 x w strips (w = 1e-4) facing each other at distance w, each two sliver triangles of
// aspect ratio 1e4: Howell C-11 for the strips.
StressRow sliverStrips(const Context& context) {
    const double w = 1e-4;
    StressRow row = rowFor(context, "sliver strips aspect 1e4", "Howell C-11, rel. error");
    TriangleMesh mesh;
    addGrid(mesh, {0, 0, 0}, {1, 0, 0}, {0, w, 0}, 1, 1);
    addGrid(mesh, {0, 0, w}, {0, w, 0}, {1, 0, 0}, 1, 1);
    const Built b = buildAll(context, mesh);
    if (!b.error.empty() && failed(row, b.error)) return row;
    row.patches = b.mesh.patchCount();
    row.finite = b.f->checkStructure().empty();
    const double exact = parallelRectangles(1, w, w), f = groupFactor(b.mesh, *b.f, 0, 2, 2, 4);
    row.error = std::abs(f - exact) / exact;
    row.tolerance = 1e-3;
    row.status = concat("F = ", formatNumber(f, 6), ", exact ", formatNumber(exact, 6));
    row.pass = row.finite && row.error <= row.tolerance;
    return row;
}

// Unit squares facing each other at a gap of `gap` (relative to their size): Howell C-11,
// F -> 1 as the gap closes.
StressRow nearlyCoincident(const Context& context, double gap, int n) {
    StressRow row =
        rowFor(context, concat("parallel gap ", formatNumber(gap)), "Howell C-11, rel. error");
    const TriangleMesh mesh = verify::parallelSquares(n, gap);
    const Built b = buildAll(context, mesh);
    if (!b.error.empty() && failed(row, b.error)) return row;
    row.patches = b.mesh.patchCount();
    row.finite = b.f->checkStructure().empty();
    const uint32_t half = uint32_t(b.mesh.patchCount() / 2);
    const double exact = parallelRectangles(1, 1, gap),
                 f = groupFactor(b.mesh, *b.f, 0, half, half, 2 * half);
    row.error = std::abs(f - exact) / exact;
    row.tolerance = 1e-3;
    row.status = concat("F = ", formatNumber(f, 7), ", exact ", formatNumber(exact, 7));
    row.pass = row.finite && row.error <= row.tolerance;
    return row;
}

// Unit squares sharing an edge at included angle phi; oracle: hingedSquares (double quadrature
// of the exact point factor), itself checked against Howell C-14 at 90 degrees.
StressRow sharedEdge(const Context& context, double degrees, int n) {
    StressRow row = rowFor(context, concat("shared edge ", formatNumber(degrees), " deg"),
                           "graded Gauss of exact point factor, rel.");
    const double phi = degrees * kPi / 180;
    static const double check =
        std::abs(hingedSquares(kPi / 2) / perpendicularRectangles(1, 1, 1) - 1);
    TriangleMesh mesh;
    addGrid(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, n, n);
    addGrid(mesh, {0, 0, 0}, {0, std::cos(phi), std::sin(phi)}, {1, 0, 0}, n, n);
    const Built b = buildAll(context, mesh);
    if (!b.error.empty() && failed(row, b.error)) return row;
    row.patches = b.mesh.patchCount();
    row.finite = b.f->checkStructure().empty();
    const uint32_t half = uint32_t(b.mesh.patchCount() / 2);
    const double exact = hingedSquares(phi), f = groupFactor(b.mesh, *b.f, 0, half, half, 2 * half);
    row.error = std::abs(f - exact) / exact;
    // 1e-3 relative, or 1e-6 absolute: float contour sums of O(1) terms leave ~1e-7.
    row.tolerance = 1e-3 + 1e-6 / exact;
    row.status = concat("F = ", formatNumber(f, 6), ", exact ", formatNumber(exact, 6),
                        ", oracle vs C-14 ", formatNumber(check, 2));
    row.pass = row.finite && row.error <= row.tolerance && check < 1e-9;
    return row;
}

// Coplanar patches see nothing of each other: F = 0 exactly. Two grids in one tilted plane far
// from the origin (so the float corners are rounded), adjacent and apart.
StressRow coplanar(const Context& context, int n) {
    StressRow row = rowFor(context, "coplanar neighbours", "F = 0 exactly, max |F|");
    const Vec3d origin{1000.37, -2000.11, 1500.53};
    const Vec3d u = Vec3d{1, 2, -0.5} * 0.9, v = Vec3d{-2, 1, 0.3} * 0.7;
    TriangleMesh mesh;
    addGrid(mesh, origin, u * n, v * n, n, n);
    addGrid(mesh, origin + u * (2.0 * n), u * n, v * n, n, n);
    const Built b = buildAll(context, mesh);
    if (!b.error.empty() && failed(row, b.error)) return row;
    row.patches = b.mesh.patchCount();
    row.finite = b.f->checkStructure().empty();
    std::vector<TransportEntry> entries;
    for (uint32_t i = 0; i < b.f->patchCount(); ++i) {
        b.f->row(i, entries);
        for (const TransportEntry& entry : entries)
            row.error = std::max(row.error, double(std::abs(entry.factor)));
    }
    row.tolerance = 0;
    row.status = concat(b.f->stats().entries, " non-zeros");
    row.pass = row.finite && row.error <= row.tolerance;
    return row;
}

// UV -> blue -> green -> red: a closed room whose floor emits UV only; the floor's fluorophore
// turns UV into blue, the ceiling's blue into green, two walls' green into red. Conservation:
// emitted = absorbed + escaped (energy.h), and the red end of the chain must be lit.
StressRow fluorescentChain(const Context& context, int n) {
    StressRow row = rowFor(context, "fluorescent chain UV>B>G>R", "energy balance |imbalance|");
    TriangleMesh mesh;
    addRoom(mesh, {0, 0, 0}, {1, 1, 1}, n);
    const Built b = buildAll(context, mesh);
    if (!b.error.empty() && failed(row, b.error)) return row;
    row.patches = b.mesh.patchCount();
    auto spec = parseWavelengthSpec("350,450,530,620");
    auto set = spec ? makeWavelengthSet(*spec) : Expected<WavelengthSet>(spec.error());
    if (!set && failed(row, set.error().message)) return row;
    const std::size_t m = set->size();
    std::vector<MaterialOperator> ops;
    for (std::size_t step = 0; step < 3; ++step) {
        std::vector<double> rho(m, 0.5), a(m, 0), e(m, 0);
        rho[step] = 0.1, a[step] = 0.8, e[step + 1] = 1;
        auto matrix = reradiationMatrix(*set, rho, a, e, 0.9, concat("chain step ", step));
        if (!matrix && failed(row, matrix.error().message)) return row;
        MaterialOperator op;
        op.matrix = std::move(*matrix);
        finishOperator(op, set->binWidthsNm());
        ops.push_back(std::move(op));
    }
    MaterialOperator white;
    white.matrix.size = m;
    white.matrix.values.assign(m * m, 0);
    for (std::size_t k = 0; k < m; ++k)
        white.matrix(k, k) = 0.5;
    finishOperator(white, set->binWidthsNm());
    ops.push_back(std::move(white));
    std::vector<double> wavelengths;
    for (std::size_t k = 0; k < m; ++k)
        wavelengths.push_back(set->wavelengthNm(k));
    RadiositySystem system = systemFor(b.mesh.areas, wavelengths, set->binWidthsNm(), ops);
    const uint32_t perFace = uint32_t(b.mesh.patchCount() / 6);
    const uint32_t faceOperator[6] = {0, 1, 2, 2, 3, 3};  // floor, ceiling, walls
    for (uint32_t p = 0; p < system.patchCount; ++p) {
        system.patchOperator[p] = faceOperator[p / perFace];
        if (p < perFace) system.emission[p * m] = 1;  // the floor emits at 350 nm only
    }
    SolverSettings settings;
    settings.tolerance = 1e-8;
    settings.threads = context.settings.threads;
    auto solved = b.f->solve(system, settings);
    if (!solved) return row.status = concat("diagnosed: ", solved.error().message), row;
    row.finite = allFinite(solved->radiosity) && b.f->checkStructure().empty();
    const EnergyBalance e =
        computeEnergyBalance(system, b.f->rowSums(), solved->radiosity, solved->gathered);
    row.error = std::abs(e.imbalance());
    // Closes to the residual (1e-8) plus F's float reciprocity (~1e-7 per entry).
    row.tolerance = 1e-5;
    const bool redLit = e.convertedInPerSample[m - 1] > 0;
    row.status = concat(solveStatus(*solved), ", red in ",
                        formatNumber(e.convertedInPerSample[m - 1], 3), " W");
    row.pass = row.finite && solved->converged && redLit && row.error <= row.tolerance;
    return row;
}

// A square of side 1e-3 at height 0.5 above the centre of [-1, 1]^2, which is split into k x k x
// 2 patches, so the small patches' rows hold ~2 k^2 entries. Oracle: Howell B-3 averaged over
// the small square. Also reports how a naive float sum of such a row would drift.
StressRow longRow(const Context& context, int k) {
    StressRow row = rowFor(context, concat("row of ", formatCount(2ull * k * k), " entries"),
                           "Howell B-3 row sum, rel. error");
    const double side = 1e-3, h = 0.5;
    TriangleMesh mesh;
    addGrid(mesh, {-side / 2, -side / 2, h}, {0, side, 0}, {side, 0, 0}, 1, 1);
    addGrid(mesh, {-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, k, k);
    const Built b = buildAll(context, mesh);
    if (!b.error.empty() && failed(row, b.error)) return row;
    row.patches = b.mesh.patchCount();
    row.finite = b.f->checkStructure().empty();
    const std::span<const double> sums = b.f->rowSums();
    const double f = (b.mesh.areas[0] * sums[0] + b.mesh.areas[1] * sums[1]) /
        (b.mesh.areas[0] + b.mesh.areas[1]);
    const double exact = smallSquareToPlane(side, h);
    row.error = std::abs(f - exact) / exact;
    row.tolerance = 1e-3;
    float naive = 0;
    std::vector<TransportEntry> first;
    b.f->row(0, first);
    for (const TransportEntry& entry : first)
        naive += entry.factor;
    row.status = concat("F = ", formatNumber(f, 7), ", exact ", formatNumber(exact, 7),
                        "; float-summed row 0 off by ",
                        formatNumber(std::abs(naive - sums[0]) / sums[0], 2), " (library: double)");
    row.pass = row.finite && row.error <= row.tolerance;
    return row;
}

}  // namespace daisy::stress
