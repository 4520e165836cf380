#include "raycast/embree_ray_caster.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "core/check.h"
#include "core/cpu_isa.h"
#include "core/strings.h"
#include "shared/intersect.h"

namespace daisy {
namespace {

// A patch's triangle as the watertight test sees it: its float corners.
struct ExactTriangle {
    shared::vec3 a, b, c;
};

}  // namespace

struct EmbreeRayCaster::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    PacketMode mode = PacketMode::Packet16;
    float selfMargin = 0;  // closest-hit tnear, scene units
    // RayCasterOptions::watertightSegments: each patch's exact triangle, read by the filters.
    std::vector<ExactTriangle> exact;

    ~Impl() {
        if (scene != nullptr) rtcReleaseScene(scene);
        if (device != nullptr) rtcReleaseDevice(device);
    }
};

namespace {

std::string deviceError(RTCDevice device) {
    switch (rtcGetDeviceError(device)) {
        case RTC_ERROR_NONE:
            return "no error";
        case RTC_ERROR_OUT_OF_MEMORY:
            return "out of memory";
        case RTC_ERROR_UNSUPPORTED_CPU:
            return "unsupported CPU";
        case RTC_ERROR_INVALID_ARGUMENT:
            return "invalid argument";
        case RTC_ERROR_INVALID_OPERATION:
            return "invalid operation";
        default:
            return "unknown error";
    }
}

// Embree's device configuration: its own choice of kernels, unless DAISY_ISA lowered the ISA
// (core/cpu_isa.h), then that ISA's kernels.
const char* embreeConfig() {
    if (cpuIsa() == processorIsa()) return nullptr;
    return cpuIsa() == CpuIsa::Avx2 ? "isa=avx2" : "isa=sse2";
}

// The watertight mode's triangles grow about their centroid by this fraction of their size, and
// by at least kGrowUlps float steps of their largest coordinate at their inradius, so that
// Embree's own test (whose rounding depends on its kernels) proposes every triangle the
// watertight test can hit (slivers grow more; a ray almost in a triangle's plane is the only
// case left where the two can disagree).
constexpr double kGrowRelative = 1.0 / 65536.0;
constexpr double kGrowUlps = 8.0;

// Corners of patch p grown as above, float.
void grownCorners(const PatchMesh& mesh, std::size_t p, float* out) {
    const auto& corners = mesh.patches[p];
    const Vec3d& a = mesh.positions[corners[0]];
    const Vec3d& b = mesh.positions[corners[1]];
    const Vec3d& c = mesh.positions[corners[2]];
    const Vec3d centroid = (a + b + c) * (1.0 / 3.0);
    const double perimeter = length(b - a) + length(c - b) + length(a - c);
    const double inradius = perimeter > 0 ? length(cross(b - a, c - a)) / perimeter : 0;
    double largest = 0;
    for (const Vec3d* v : {&a, &b, &c})
        largest = std::max({largest, std::abs(v->x), std::abs(v->y), std::abs(v->z)});
    const double ulp = largest * std::numeric_limits<float>::epsilon();
    const double grow =
        inradius > 0 ? std::max(kGrowRelative, kGrowUlps * ulp / inradius) : kGrowRelative;
    for (int k = 0; k < 3; ++k) {
        const Vec3d& v = mesh.positions[corners[k]];
        const Vec3d g = v + (v - centroid) * grow;
        out[3 * k + 0] = static_cast<float>(g.x);
        out[3 * k + 1] = static_cast<float>(g.y);
        out[3 * k + 2] = static_cast<float>(g.z);
    }
}

// The watertight mode's filters: Embree's candidate hit on a grown triangle stands only when the
// shared watertight test (shared/intersect.h, the reference backend's) hits the patch's exact
// triangle, for a segment at kSegmentMargin < t < 1 - kSegmentMargin (occlusion) or for a
// closest-hit ray beyond its tnear. The ray is rebuilt from Embree's copy of it, bit for bit.
template <bool kSegment>
void watertightFilter(const RTCFilterFunctionNArguments* args) {
    const auto* exact = static_cast<const ExactTriangle*>(args->geometryUserPtr);
    const unsigned n = args->N;
    RTCRayN* ray = args->ray;
    for (unsigned k = 0; k < n; ++k) {
        if (args->valid[k] == 0) continue;
        const ExactTriangle& e = exact[RTCHitN_primID(args->hit, n, k)];
        const shared::vec3 org(RTCRayN_org_x(ray, n, k), RTCRayN_org_y(ray, n, k),
                               RTCRayN_org_z(ray, n, k));
        const shared::vec3 dir(RTCRayN_dir_x(ray, n, k), RTCRayN_dir_y(ray, n, k),
                               RTCRayN_dir_z(ray, n, k));
        const float tmin = kSegment ? RayCaster::kSegmentMargin : RTCRayN_tnear(ray, n, k);
        const float tmax =
            kSegment ? 1.0f - RayCaster::kSegmentMargin : std::numeric_limits<float>::infinity();
        float t = 0;
        if (!shared::intersectTriangle(shared::makeWatertightRay(org, dir), e.a, e.b, e.c, tmin,
                                       tmax, t)) {
            args->valid[k] = 0;
        }
    }
}

// Segment k as a ray: origin, direction end - origin, t in [margin, 1 - margin]; in the
// watertight mode [0, 1], the filter applying the margins (a wider span, so Embree's rounding of
// t cannot drop a candidate).
void setSegmentRay(const SegmentArrays& s, std::size_t k, bool watertight, float& ox, float& oy,
                   float& oz, float& dx, float& dy, float& dz, float& tnear, float& tfar) {
    ox = s.x0[k];
    oy = s.y0[k];
    oz = s.z0[k];
    dx = s.x1[k] - s.x0[k];
    dy = s.y1[k] - s.y0[k];
    dz = s.z1[k] - s.z0[k];
    tnear = watertight ? 0.0f : RayCaster::kSegmentMargin;
    tfar = watertight ? 1.0f : 1.0f - RayCaster::kSegmentMargin;
}

// Packets of N segments. The context is incoherent: Embree's coherent traversal culls the BVH
// with one frustum per packet that assumes every ray shares one direction octant
// (kernels/bvh/node_intersector_frustum.h), and a packet of shadow segments (a pair's points on
// both patches, or several pairs) mixes directions: it missed hits deep inside triangles, which
// ones depending on the packet's other rays and on Embree's kernels (ISA).
template <int N, typename RayN>
void occludedPackets(RTCScene scene, bool watertight, const SegmentArrays& segments,
                     std::span<uint8_t> blocked,
                     void (*occludedN)(const int*, RTCScene, RTCIntersectContext*, RayN*)) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    alignas(64) RayN packet;
    alignas(64) int valid[N];
    for (int k = 0; k < N; ++k) {
        packet.time[k] = 0;
        packet.mask[k] = 0xffffffffu;
        packet.id[k] = 0;
        packet.flags[k] = 0;
    }
    const std::size_t total = segments.size();
    for (std::size_t base = 0; base < total; base += N) {
        const std::size_t count = std::min<std::size_t>(N, total - base);
        for (int k = 0; k < N; ++k) {
            const std::size_t s = base + std::min<std::size_t>(k, count - 1);
            valid[k] = std::size_t(k) < count && !segments.empty(s) ? -1 : 0;
            setSegmentRay(segments, s, watertight, packet.org_x[k], packet.org_y[k],
                          packet.org_z[k], packet.dir_x[k], packet.dir_y[k], packet.dir_z[k],
                          packet.tnear[k], packet.tfar[k]);
        }
        occludedN(valid, scene, &context, &packet);
        for (std::size_t k = 0; k < count; ++k)  // Embree sets tfar = -inf on a hit
            blocked[base + k] = valid[k] != 0 && packet.tfar[k] < 0 ? 1 : 0;
    }
}

}  // namespace

Expected<std::unique_ptr<EmbreeRayCaster>> EmbreeRayCaster::create(
    const PatchMesh& mesh, const RayCasterOptions& options) {
    auto impl = std::make_unique<Impl>();
    impl->mode = options.packetMode;
    impl->device = rtcNewDevice(embreeConfig());
    if (impl->device == nullptr) {
        return Error{
            concat("ray caster: Embree could not create a device (", deviceError(nullptr), ")")};
    }
    impl->scene = rtcNewScene(impl->device);
    rtcSetSceneBuildQuality(impl->scene, RTC_BUILD_QUALITY_HIGH);
    if (options.robust) rtcSetSceneFlags(impl->scene, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry geometry = rtcNewGeometry(impl->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // The watertight mode gives every patch its own three (grown) corners.
    const bool watertight = options.watertightSegments;
    const std::size_t vertexCount = watertight ? 3 * mesh.patchCount() : mesh.vertexCount();
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                3 * sizeof(float), std::max<std::size_t>(1, vertexCount)));
    auto* indices = static_cast<uint32_t*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(uint32_t), mesh.patchCount()));
    if (vertices == nullptr || (indices == nullptr && mesh.patchCount() > 0)) {
        const std::string why = deviceError(impl->device);
        rtcReleaseGeometry(geometry);
        return Error{concat("ray caster: Embree could not allocate the scene (", why, ")")};
    }
    Bounds3d bounds;
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
        bounds.extend(mesh.positions[v]);
    if (watertight) {
        impl->exact.resize(mesh.patchCount());
        const auto corner = [&](uint32_t v) {
            return shared::vec3(static_cast<float>(mesh.positions[v].x),
                                static_cast<float>(mesh.positions[v].y),
                                static_cast<float>(mesh.positions[v].z));
        };
        for (std::size_t p = 0; p < mesh.patchCount(); ++p) {
            const auto& c = mesh.patches[p];
            impl->exact[p] = {corner(c[0]), corner(c[1]), corner(c[2])};
            grownCorners(mesh, p, vertices + 9 * p);
            for (uint32_t k = 0; k < 3; ++k)
                indices[3 * p + k] = static_cast<uint32_t>(3 * p + k);
        }
        rtcSetGeometryUserData(geometry, impl->exact.data());
        rtcSetGeometryOccludedFilterFunction(geometry, watertightFilter<true>);
        rtcSetGeometryIntersectFilterFunction(geometry, watertightFilter<false>);
    } else {
        for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
            vertices[3 * v + 0] = static_cast<float>(mesh.positions[v].x);
            vertices[3 * v + 1] = static_cast<float>(mesh.positions[v].y);
            vertices[3 * v + 2] = static_cast<float>(mesh.positions[v].z);
        }
        for (std::size_t p = 0; p < mesh.patchCount(); ++p)
            std::memcpy(indices + 3 * p, mesh.patches[p].data(), 3 * sizeof(uint32_t));
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(impl->scene, geometry, 0);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(impl->scene);
    if (rtcGetDeviceError(impl->device) != RTC_ERROR_NONE) {
        return Error{concat("ray caster: Embree could not build the scene (",
                            deviceError(impl->device), ")")};
    }
    // Closest-hit rays start on their patch: skip hits nearer than float rounding at the
    // scene's scale, times a safety factor.
    impl->selfMargin = static_cast<float>(1e-6 * std::max(1e-30, bounds.diagonal()));
    return std::unique_ptr<EmbreeRayCaster>(new EmbreeRayCaster(std::move(impl)));
}

EmbreeRayCaster::EmbreeRayCaster(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
EmbreeRayCaster::~EmbreeRayCaster() = default;

PacketMode EmbreeRayCaster::packetMode() const {
    return impl_->mode;
}
void EmbreeRayCaster::setPacketMode(PacketMode mode) {
    impl_->mode = mode;
}

void EmbreeRayCaster::occluded(const SegmentArrays& segments, std::span<uint8_t> blocked) const {
    RTCScene scene = impl_->scene;
    const bool watertight = !impl_->exact.empty();
    switch (impl_->mode) {
        case PacketMode::Single: {
            RTCIntersectContext context;
            rtcInitIntersectContext(&context);
            for (std::size_t k = 0; k < segments.size(); ++k) {
                blocked[k] = 0;
                if (segments.empty(k)) continue;
                RTCRay ray;
                setSegmentRay(segments, k, watertight, ray.org_x, ray.org_y, ray.org_z, ray.dir_x,
                              ray.dir_y, ray.dir_z, ray.tnear, ray.tfar);
                ray.time = 0;
                ray.mask = 0xffffffffu;
                ray.id = 0;
                ray.flags = 0;
                rtcOccluded1(scene, &context, &ray);
                blocked[k] = ray.tfar < 0 ? 1 : 0;
            }
            return;
        }
        case PacketMode::Packet4:
            occludedPackets<4, RTCRay4>(scene, watertight, segments, blocked, rtcOccluded4);
            return;
        case PacketMode::Packet8:
            occludedPackets<8, RTCRay8>(scene, watertight, segments, blocked, rtcOccluded8);
            return;
        case PacketMode::Packet16:
            occludedPackets<16, RTCRay16>(scene, watertight, segments, blocked, rtcOccluded16);
            return;
        case PacketMode::Stream: {
            RTCIntersectContext context;
            rtcInitIntersectContext(&context);
            context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;  // as occludedPackets
            constexpr std::size_t kBatch = 256;
            alignas(64) RTCRay rays[kBatch];
            uint32_t source[kBatch];
            std::size_t next = 0;
            while (next < segments.size()) {
                std::size_t count = 0;
                for (; next < segments.size() && count < kBatch; ++next) {
                    blocked[next] = 0;
                    if (segments.empty(next)) continue;
                    source[count] = static_cast<uint32_t>(next);
                    RTCRay& ray = rays[count++];
                    setSegmentRay(segments, next, watertight, ray.org_x, ray.org_y, ray.org_z,
                                  ray.dir_x, ray.dir_y, ray.dir_z, ray.tnear, ray.tfar);
                    ray.time = 0;
                    ray.mask = 0xffffffffu;
                    ray.id = 0;
                    ray.flags = 0;
                }
                rtcOccluded1M(scene, &context, rays, static_cast<unsigned>(count), sizeof(RTCRay));
                for (std::size_t k = 0; k < count; ++k)
                    blocked[source[k]] = rays[k].tfar < 0 ? 1 : 0;
            }
            return;
        }
    }
}

namespace {

// An Embree ray from `ray` over (tNear, infinity) with no hit yet.
RTCRayHit unboundedRayHit(const Ray& ray, float tNear) {
    RTCRayHit rayHit{};
    rayHit.ray.org_x = ray.origin[0];
    rayHit.ray.org_y = ray.origin[1];
    rayHit.ray.org_z = ray.origin[2];
    rayHit.ray.dir_x = ray.direction[0];
    rayHit.ray.dir_y = ray.direction[1];
    rayHit.ray.dir_z = ray.direction[2];
    rayHit.ray.tnear = tNear;
    rayHit.ray.tfar = std::numeric_limits<float>::infinity();
    rayHit.ray.mask = 0xffffffffu;
    rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rayHit.hit.primID = RTC_INVALID_GEOMETRY_ID;
    return rayHit;
}

}  // namespace

void EmbreeRayCaster::closestHits(std::span<const Ray> rays, std::span<uint32_t> hits) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (std::size_t k = 0; k < rays.size(); ++k) {
        RTCRayHit rayHit = unboundedRayHit(rays[k], impl_->selfMargin);
        rtcIntersect1(impl_->scene, &context, &rayHit);
        hits[k] = rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID ? kNoPatch : rayHit.hit.primID;
    }
}

void EmbreeRayCaster::closestSurfaceHits(std::span<const Ray> rays, std::span<SurfaceHit> hits,
                                         float tNear) const {
    DAISY_CHECK(rays.size() == hits.size());
    DAISY_CHECK(impl_->exact.empty());  // barycentrics of the grown triangles: see ray_caster.h
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;  // callers pass neighbouring pixels
    for (std::size_t k = 0; k < rays.size(); ++k) {
        RTCRayHit rayHit = unboundedRayHit(rays[k], tNear);
        rtcIntersect1(impl_->scene, &context, &rayHit);
        if (rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
            hits[k] = {kNoPatch, 0, 0, std::numeric_limits<float>::infinity()};
        } else {
            hits[k] = {rayHit.hit.primID, rayHit.hit.u, rayHit.hit.v, rayHit.ray.tfar};
        }
    }
}

}  // namespace daisy
