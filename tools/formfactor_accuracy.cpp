// Accuracy of the view-factor methods against closed forms and conservation laws, as the
// Markdown table in docs/formfactors.md. Oracles: Howell's catalogue C-11 (parallel unit squares
// at distance 1: 0.199824895698) and C-14 (perpendicular unit squares sharing an edge:
// 0.200043776075); the summation rule in a closed unit cube (every row of F sums to 1); a plate
// halfway between two squares at distance 2 that hides exactly half (F = C-11(X = Y = 0.5) / 2
// = 0.0342947944). Usage: formfactor_accuracy [--threads T]; prints the table on stdout.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "backend/embree_ray_caster.h"
#include "radiosity/form_factors.h"

using namespace daisy;

namespace {

constexpr double kC11 = 0.199824895698;
constexpr double kC14 = 0.200043776075;
constexpr double kHalfHidden = 0.5 * 0.0685895888185526;

void addGrid(TriangleMesh& mesh, Vec3d origin, Vec3d u, Vec3d v, int n) {
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    for (int y = 0; y <= n; ++y) {
        for (int x = 0; x <= n; ++x)
            mesh.positions.push_back(origin + u * (double(x) / n) + v * (double(y) / n));
    }
    const auto at = [&](int x, int y) { return base + uint32_t(y * (n + 1) + x); };
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            mesh.triangles.push_back({at(x, y), at(x + 1, y), at(x + 1, y + 1)});
            mesh.triangles.push_back({at(x, y), at(x + 1, y + 1), at(x, y + 1)});
            mesh.materials.insert(mesh.materials.end(), {0u, 0u});
        }
    }
}

struct Run {
    SparseMatrix matrix;
    PatchMesh mesh;
    double seconds = 0;
};

Run run(const TriangleMesh& triangles, const FormFactorSettings& settings) {
    Run r;
    r.mesh = std::move(buildPatchMesh(triangles, 0).value());
    auto caster = EmbreeRayCaster::create(r.mesh);
    const auto start = std::chrono::steady_clock::now();
    auto result = computeFormFactors(r.mesh, settings, **caster);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.matrix = std::move(result->matrix);
    return r;
}

// Area-weighted factor from the first `count` patches to the next `count`.
double groupFactor(const Run& r, uint32_t count) {
    double flux = 0, area = 0;
    for (uint32_t i = 0; i < count; ++i) {
        area += r.mesh.areas[i];
        for (uint32_t j = count; j < 2 * count; ++j)
            flux += r.mesh.areas[i] * r.matrix.at(i, j);
    }
    return flux / area;
}

double squares(const FormFactorSettings& settings, int n, bool perpendicular) {
    TriangleMesh mesh;
    addGrid(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, n);
    if (perpendicular) {
        addGrid(mesh, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, n);
    } else {
        addGrid(mesh, {0, 0, 1}, {0, 1, 0}, {1, 0, 0}, n);
    }
    return groupFactor(run(mesh, settings), uint32_t(2 * n * n)) / (perpendicular ? kC14 : kC11) -
        1;
}

// Largest |row sum - 1| in the unit cube room with n x n quads a face, and the build time.
std::pair<double, double> cube(const FormFactorSettings& settings, int n) {
    TriangleMesh mesh;
    const Vec3d o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
    addGrid(mesh, o, x, y, n);
    addGrid(mesh, z, y, x, n);
    addGrid(mesh, o, z, x, n);
    addGrid(mesh, y, x, z, n);
    addGrid(mesh, o, y, z, n);
    addGrid(mesh, x, z, y, n);
    const Run r = run(mesh, settings);
    double worst = 0;
    for (double sum : rowSums(r.matrix))
        worst = std::max(worst, std::fabs(sum - 1));
    return {worst, r.seconds};
}

double halfHidden(const FormFactorSettings& settings) {
    TriangleMesh mesh;
    addGrid(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 8);
    addGrid(mesh, {0, 0, 2}, {0, 1, 0}, {1, 0, 0}, 8);
    addGrid(mesh, {-1, -1, 1}, {1.5, 0, 0}, {0, 3, 0}, 1);
    return groupFactor(run(mesh, settings), 128) / kHalfHidden - 1;
}

}  // namespace

int main(int argc, char** argv) {
    FormFactorSettings base;
    base.progress = false;
    for (int a = 1; a + 1 < argc; ++a) {
        if (std::strcmp(argv[a], "--threads") == 0) base.threads = std::atoi(argv[a + 1]);
    }
    struct Setting {
        FormFactorMethod method;
        int level, rays, stochasticRays;
    };
    const std::vector<Setting> settings = {
        {FormFactorMethod::Riemann, 0, 16, 0},       {FormFactorMethod::Riemann, 1, 16, 0},
        {FormFactorMethod::Riemann, 2, 16, 0},       {FormFactorMethod::Riemann, 3, 16, 0},
        {FormFactorMethod::Nusselt, 0, 16, 0},       {FormFactorMethod::Hybrid, 0, 16, 0},
        {FormFactorMethod::Hybrid, 1, 16, 0},        {FormFactorMethod::Hybrid, 2, 16, 0},
        {FormFactorMethod::Hybrid, 1, 1, 0},         {FormFactorMethod::Hybrid, 1, 4, 0},
        {FormFactorMethod::Hybrid, 1, 64, 0},        {FormFactorMethod::Stochastic, 0, 0, 256},
        {FormFactorMethod::Stochastic, 0, 0, 1024},  {FormFactorMethod::Stochastic, 0, 0, 4096},
        {FormFactorMethod::Stochastic, 0, 0, 16384},
    };
    std::printf(
        "| method | L | K | N | C-11, 2 tri | C-11, 32 tri | C-14, 2 tri | C-14, 32 tri | "
        "cube 2x2 max abs(row-1) | cube 6x6 max abs(row-1) | half hidden | cube 6x6 time |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const Setting& s : settings) {
        FormFactorSettings f = base;
        f.method = s.method;
        f.quadratureLevel = s.level;
        f.raysPerPair = s.rays;
        f.stochasticRays = std::max(1, s.stochasticRays);
        const bool stochastic = s.method == FormFactorMethod::Stochastic;
        const auto [coarse, coarseSeconds] = cube(f, 2);
        const auto [fine, fineSeconds] = cube(f, 6);
        (void)coarseSeconds;
        std::printf(
            "| %s | %s | %s | %s | %+.1e | %+.1e | %+.1e | %+.1e | %.1e | %.1e | %+.1e | "
            "%.0f ms |\n",
            formFactorMethodName(s.method),
            stochastic || s.method == FormFactorMethod::Nusselt ? "-"
                                                                : std::to_string(s.level).c_str(),
            stochastic ? "-" : std::to_string(s.rays).c_str(),
            stochastic ? std::to_string(s.stochasticRays).c_str() : "-", squares(f, 1, false),
            squares(f, 4, false), squares(f, 1, true), squares(f, 4, true), coarse, fine,
            halfHidden(f), 1e3 * fineSeconds);
    }
    return 0;
}
