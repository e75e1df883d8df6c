// Packet (4/8/16, partial valid masks) and stream (1M, 1Mp, NM, Np) queries through obvh and
// Debian's Embree: active lanes must agree, inactive lanes must stay untouched.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "crossval_harness.h"
#include "ray_generation.h"
#include "stack_generator.h"
#include "test_scenes.h"

namespace obvh::test {
namespace {

constexpr size_t kRays = 100000;

SceneData packetScene() {
  SceneData scene;
  scene.name = "packets";
  scene.meshes.push_back(randomTriangleSoup(10000, 21));
  scene.meshes.push_back(quadGrid(30, 0.3f, 22));
  MeshData grids = gridPatches(30, 0.3f, 25);
  const float offset[3] = {0.f, 0.f, 0.4f};
  transformMesh(grids, 1.f, offset);
  scene.meshes.push_back(grids);
  const float center[3] = {0.5f, 0.5f, 0.5f};
  scene.meshes.push_back(icosphere(3, 0.3f, center));
  return scene;
}

struct Fixture {
  SceneData scene;
  const LoadedLibraries& libs = libraries();
  RTCDevice obvhDevice;  // the default device unless a test brings its own config
  tools::CommittedScene reference{*libs.embree, libs.embreeDevice, scene};
  tools::CommittedScene candidate{*libs.obvh, obvhDevice, scene};
  std::vector<RTCRay> rays = mixedRays(scene, kRays / 2, 224, 23);  // 50000 random + 50176 coherent
  RTCIntersectContext context;
  explicit Fixture(SceneData traced = packetScene(), RTCDevice device = nullptr)
      : scene(std::move(traced)), obvhDevice(device ? device : libraries().obvhDevice) {
    rtcInitIntersectContext(&context);
    assignMasks(rays, 24);
  }
};

template <int W, typename Packet>
void loadPacket(Packet& p, const std::vector<RTCRay>& rays, size_t first) {
  std::memset(&p, 0, sizeof(p));
  RTCRayHitN* n = reinterpret_cast<RTCRayHitN*>(&p);
  for (unsigned i = 0; i < W; ++i) {
    RTCRayHit one{};
    one.ray = rays[(first + i) % rays.size()];
    one.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    one.hit.primID = 0xABCDu;
    one.hit.instID[0] = 0x1234u;
    RTCRayN* r = RTCRayHitN_RayN(n, W);
    RTCRayN_org_x(r, W, i) = one.ray.org_x, RTCRayN_org_y(r, W, i) = one.ray.org_y, RTCRayN_org_z(r, W, i) = one.ray.org_z;
    RTCRayN_dir_x(r, W, i) = one.ray.dir_x, RTCRayN_dir_y(r, W, i) = one.ray.dir_y, RTCRayN_dir_z(r, W, i) = one.ray.dir_z;
    RTCRayN_tnear(r, W, i) = one.ray.tnear, RTCRayN_tfar(r, W, i) = one.ray.tfar, RTCRayN_mask(r, W, i) = one.ray.mask;
    RTCRayN_time(r, W, i) = one.ray.time;
    RTCRayN_id(r, W, i) = unsigned(first + i);
    rtcCopyHitToHitN(RTCRayHitN_HitN(n, W), &one.hit, W, i);
  }
}

// Compares one lane: active lanes by the judge, inactive lanes must equal the input bit for bit.
template <int W, typename Packet>
void compareLanes(const SceneData& scene, const Packet& input, const Packet& a, const Packet& b, const int* valid,
                  CrossvalCounts& counts, size_t& touchedInactive) {
  auto* in = reinterpret_cast<RTCRayHitN*>(const_cast<Packet*>(&input));
  auto* pa = reinterpret_cast<RTCRayHitN*>(const_cast<Packet*>(&a));
  auto* pb = reinterpret_cast<RTCRayHitN*>(const_cast<Packet*>(&b));
  for (unsigned i = 0; i < W; ++i) {
    const RTCRayHit original = rtcGetRayHitFromRayHitN(in, W, i);
    const RTCRayHit ra = rtcGetRayHitFromRayHitN(pa, W, i), rb = rtcGetRayHitFromRayHitN(pb, W, i);
    if (valid[i] != -1) {
      if (std::memcmp(&original, &rb, sizeof(RTCRayHit)) != 0) ++touchedInactive;
      continue;
    }
    counts.add(tools::compareHits(scene, original.ray, tools::toHitRecord(ra), tools::toHitRecord(rb)), original.ray);
  }
}

template <int W, typename Packet, typename Intersect>
void runIntersectPackets(Fixture& f, Intersect embreeCall, Intersect obvhCall, const char* name) {
  std::mt19937 rng(W);
  CrossvalCounts counts;
  size_t touchedInactive = 0;
  for (size_t first = 0; first < f.rays.size(); first += W) {
    alignas(64) int valid[W];
    for (int i = 0; i < W; ++i) valid[i] = (rng() % 4 == 0) ? 0 : -1;  // about a quarter inactive
    alignas(64) Packet input, a, b;
    loadPacket<W>(input, f.rays, first);
    a = input, b = input;
    embreeCall(valid, f.reference.scene(), &f.context, &a);
    obvhCall(valid, f.candidate.scene(), &f.context, &b);
    compareLanes<W>(f.scene, input, a, b, valid, counts, touchedInactive);
  }
  std::printf("[crossval] %-34s %s\n", name, counts.summary().c_str());
  EXPECT_EQ(counts.mismatched, 0u) << counts.summary();
  EXPECT_EQ(touchedInactive, 0u) << "obvh wrote to inactive lanes";
}

template <int W, typename RayPacket, typename Occluded>
void runOccludedPackets(Fixture& f, Occluded embreeCall, Occluded obvhCall, const char* name) {
  std::mt19937 rng(W + 100);
  CrossvalCounts counts;
  size_t touchedInactive = 0;
  for (size_t first = 0; first < f.rays.size() / 4; first += W) {
    alignas(64) int valid[W];
    for (int i = 0; i < W; ++i) valid[i] = (rng() % 4 == 0) ? 0 : -1;
    alignas(64) RTCRayHitNt<W> packet;
    loadPacket<W>(packet, f.rays, first);
    alignas(64) RayPacket input, a, b;
    std::memcpy(&input, &packet.ray, sizeof(RayPacket));
    a = input, b = input;
    embreeCall(valid, f.reference.scene(), &f.context, &a);
    obvhCall(valid, f.candidate.scene(), &f.context, &b);
    for (int i = 0; i < W; ++i) {
      if (valid[i] != -1) {
        if (b.tfar[i] != input.tfar[i]) ++touchedInactive;
        continue;
      }
      const float hit = -std::numeric_limits<float>::infinity();
      judgeOcclusion(f.scene, f.rays[(first + i) % f.rays.size()], a.tfar[i] == hit, b.tfar[i] == hit, counts);
    }
  }
  std::printf("[crossval] %-34s %s\n", name, counts.summary().c_str());
  EXPECT_EQ(counts.mismatched, 0u) << counts.summary();
  EXPECT_EQ(touchedInactive, 0u) << "obvh wrote to inactive lanes";
}

// rtcIntersect4/8/16 and rtcOccluded4/8/16 over the fixture's rays; labels end in `suffix`.
void runIntersectPacketWidths(Fixture& f, const std::string& suffix) {
  runIntersectPackets<4, RTCRayHit4>(f, f.libs.embree->rtcIntersect4, f.libs.obvh->rtcIntersect4,
                                     ("rtcIntersect4" + suffix).c_str());
  runIntersectPackets<8, RTCRayHit8>(f, f.libs.embree->rtcIntersect8, f.libs.obvh->rtcIntersect8,
                                     ("rtcIntersect8" + suffix).c_str());
  runIntersectPackets<16, RTCRayHit16>(f, f.libs.embree->rtcIntersect16, f.libs.obvh->rtcIntersect16,
                                       ("rtcIntersect16" + suffix).c_str());
}

void runOccludedPacketWidths(Fixture& f, const std::string& suffix) {
  runOccludedPackets<4, RTCRay4>(f, f.libs.embree->rtcOccluded4, f.libs.obvh->rtcOccluded4, ("rtcOccluded4" + suffix).c_str());
  runOccludedPackets<8, RTCRay8>(f, f.libs.embree->rtcOccluded8, f.libs.obvh->rtcOccluded8, ("rtcOccluded8" + suffix).c_str());
  runOccludedPackets<16, RTCRay16>(f, f.libs.embree->rtcOccluded16, f.libs.obvh->rtcOccluded16,
                                   ("rtcOccluded16" + suffix).c_str());
}

TEST(CrossvalPackets, Intersect4_8_16WithPartialValidMasks) {
  Fixture f;
  runIntersectPacketWidths(f, "");
}

TEST(CrossvalPackets, Occluded4_8_16WithPartialValidMasks) {
  Fixture f;
  runOccludedPacketWidths(f, "");
}

// Orthographic cameras along -z (the tools' orthographicRays), +x and -y: every packet's rays share
// a direction that does not move along two axes, and the packet walks together (PacketLanes'
// zero axes), with many rays in the planes of the grid's and the patches' boxes.
TEST(CrossvalPackets, OrthographicPackets) {
  Fixture f;
  RTCBounds b;
  f.libs.embree->rtcGetSceneBounds(f.reference.scene(), &b);
  const tools::SceneBox box{{b.lower_x, b.lower_y, b.lower_z}, {b.upper_x, b.upper_y, b.upper_z}};
  const std::vector<RTCRay> alongZ = tools::orthographicRays(box, 160, 160);
  f.rays.clear();
  for (int view = 0; view < 3; ++view)
    for (const RTCRay& z : alongZ) {
      RTCRay r = z;
      if (view == 1) {  // along +x: the view's (x, y, z) become (z, x, y), the direction negated
        r.org_x = box.lower[0] - (z.org_z - box.upper[2]), r.org_y = z.org_x, r.org_z = z.org_y;
        r.dir_x = -z.dir_z, r.dir_y = z.dir_x, r.dir_z = z.dir_y;
      } else if (view == 2) {  // along -y: (x, y, z) become (y, z, x)
        r.org_x = z.org_y, r.org_y = box.upper[1] + (z.org_z - box.upper[2]), r.org_z = z.org_x;
        r.dir_x = z.dir_y, r.dir_y = z.dir_z, r.dir_z = z.dir_x;
      }
      f.rays.push_back(r);
    }
  assignMasks(f.rays, 24);
  runIntersectPacketWidths(f, ", orthographic");
  runOccludedPacketWidths(f, ", orthographic");
}

// Packets through the eight-wide oriented layouts, traced together (obb_packets, on by default)
// where their rays share direction signs, as the coherent half of the rays do.
TEST(CrossvalPackets, OrientedLayoutPacketsOnStacks) {
  for (const char* config : {"accel=obb", "accel=hybrid"}) {
    const ObvhDevice device(config);
    ASSERT_NE(device.get(), nullptr);
    for (const char* name : {"small-1.5k", "mixed-6.9k"}) {
      Fixture f(tools::generateStack(tools::findStackPreset(name)->params, name).asScene(), device.get());
      runIntersectPacketWidths(f, std::string(", ") + config + ", " + name);
    }
  }
}

// Valid lanes whose segment is empty (tnear > tfar, as shadow rays behind pixels without a hit are
// made) or a single point (tnear == tfar), scattered and in runs of 32 that fill whole packets.
TEST(CrossvalPackets, EmptySegmentsAreAnsweredLikeEmbree) {
  Fixture f;
  for (size_t i = 0; i < f.rays.size(); ++i) {
    RTCRay& r = f.rays[i];
    if (i % 3 == 0 || (i / 32) % 5 == 0) {
      r.tnear = 1.f, r.tfar = 0.f;
    } else if (i % 7 == 0) {
      r.tnear = r.tfar = 0.5f;
    }
  }
  runIntersectPacketWidths(f, ", empty segments");
  runOccludedPacketWidths(f, ", empty segments");
}

// Motion blur: each lane is traced at its own time.
TEST(CrossvalPackets, MotionBlurLanesTraceAtTheirOwnTime) {
  SceneData scene;
  scene.name = "moving packets";
  scene.meshes.push_back(moving(randomTriangleSoup(5000, 26), 3, 27));
  scene.meshes.push_back(moving(quadGrid(20, 0.3f, 28), 2, 29));
  scene.meshes.push_back(randomTriangleSoup(2000, 30));
  Fixture f(scene);
  assignRandomTimes(f.rays, 31);
  runIntersectPacketWidths(f, ", motion blur");
  runOccludedPacketWidths(f, ", motion blur");
}

std::vector<RTCRayHit> asRayHits(const std::vector<RTCRay>& rays) {
  std::vector<RTCRayHit> out(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    out[i].ray = rays[i];
    out[i].hit.geomID = RTC_INVALID_GEOMETRY_ID;
  }
  return out;
}

void expectStreamAgrees(Fixture& f, const std::vector<RTCRayHit>& a, const std::vector<RTCRayHit>& b, const char* name) {
  CrossvalCounts counts;
  for (size_t i = 0; i < a.size(); ++i)
    counts.add(tools::compareHits(f.scene, f.rays[i], tools::toHitRecord(a[i]), tools::toHitRecord(b[i])), f.rays[i]);
  std::printf("[crossval] %-34s %s\n", name, counts.summary().c_str());
  EXPECT_EQ(counts.mismatched, 0u) << counts.summary();
}

void expectIntersect1MAnd1MpAgree(Fixture& f, const std::string& suffix = "") {
  std::vector<RTCRayHit> a = asRayHits(f.rays), b = a;
  f.libs.embree->rtcIntersect1M(f.reference.scene(), &f.context, a.data(), unsigned(a.size()), sizeof(RTCRayHit));
  f.libs.obvh->rtcIntersect1M(f.candidate.scene(), &f.context, b.data(), unsigned(b.size()), sizeof(RTCRayHit));
  expectStreamAgrees(f, a, b, ("rtcIntersect1M" + suffix).c_str());

  std::vector<RTCRayHit> c = asRayHits(f.rays), d = c;
  std::vector<RTCRayHit*> pc, pd;
  for (size_t i = 0; i < c.size(); ++i) pc.push_back(&c[i]), pd.push_back(&d[i]);
  f.libs.embree->rtcIntersect1Mp(f.reference.scene(), &f.context, pc.data(), unsigned(pc.size()));
  f.libs.obvh->rtcIntersect1Mp(f.candidate.scene(), &f.context, pd.data(), unsigned(pd.size()));
  expectStreamAgrees(f, c, d, ("rtcIntersect1Mp" + suffix).c_str());
}

TEST(CrossvalStreams, Intersect1MAnd1Mp) {
  Fixture f;
  expectIntersect1MAnd1MpAgree(f);
}

// Declared coherent, obvh traces these streams as packets of consecutive rays (Embree too).
TEST(CrossvalStreams, CoherentIntersect1MAnd1Mp) {
  Fixture f;
  f.context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  expectIntersect1MAnd1MpAgree(f, " (coherent)");
}

void expectIntersectNMAndNpAgree(Fixture& f, const std::string& suffix = "") {
  constexpr unsigned N = 8;
  const unsigned M = unsigned(f.rays.size() / N);
  std::vector<RTCRayHitNt<N>> a(M), b;
  for (unsigned m = 0; m < M; ++m) loadPacket<N>(a[m], f.rays, size_t(m) * N);
  b = a;
  f.libs.embree->rtcIntersectNM(f.reference.scene(), &f.context, reinterpret_cast<RTCRayHitN*>(a.data()), N, M,
                                sizeof(RTCRayHitNt<N>));
  f.libs.obvh->rtcIntersectNM(f.candidate.scene(), &f.context, reinterpret_cast<RTCRayHitN*>(b.data()), N, M,
                              sizeof(RTCRayHitNt<N>));
  std::vector<RTCRayHit> ua, ub;
  for (unsigned m = 0; m < M; ++m)
    for (unsigned i = 0; i < N; ++i) {
      ua.push_back(rtcGetRayHitFromRayHitN(reinterpret_cast<RTCRayHitN*>(&a[m]), N, i));
      ub.push_back(rtcGetRayHitFromRayHitN(reinterpret_cast<RTCRayHitN*>(&b[m]), N, i));
    }
  expectStreamAgrees(f, ua, ub, ("rtcIntersectNM (N=8)" + suffix).c_str());

  // Np: one array per member.
  const size_t n = f.rays.size();
  struct Soa {
    std::vector<float> ox, oy, oz, tn, dx, dy, dz, time, tf, ngx, ngy, ngz, u, v;
    std::vector<unsigned> mask, id, flags, prim, geom, inst;
    RTCRayHitNp np{};
    explicit Soa(const std::vector<RTCRay>& rays) {
      for (const RTCRay& r : rays) {
        ox.push_back(r.org_x), oy.push_back(r.org_y), oz.push_back(r.org_z), tn.push_back(r.tnear);
        dx.push_back(r.dir_x), dy.push_back(r.dir_y), dz.push_back(r.dir_z), time.push_back(0.f), tf.push_back(r.tfar);
        mask.push_back(r.mask), id.push_back(0), flags.push_back(0);
      }
      ngx.resize(rays.size()), ngy.resize(rays.size()), ngz.resize(rays.size()), u.resize(rays.size()), v.resize(rays.size());
      prim.resize(rays.size()), geom.assign(rays.size(), RTC_INVALID_GEOMETRY_ID), inst.resize(rays.size());
      np.ray = {ox.data(), oy.data(), oz.data(), tn.data(), dx.data(), dy.data(), dz.data(), time.data(), tf.data(),
                mask.data(), id.data(), flags.data()};
      np.hit.Ng_x = ngx.data(), np.hit.Ng_y = ngy.data(), np.hit.Ng_z = ngz.data(), np.hit.u = u.data();
      np.hit.v = v.data(), np.hit.primID = prim.data(), np.hit.geomID = geom.data(), np.hit.instID[0] = inst.data();
    }
    RTCRayHit at(size_t i) const {
      RTCRayHit h{};
      h.ray.tfar = tf[i];
      h.hit = {ngx[i], ngy[i], ngz[i], u[i], v[i], prim[i], geom[i], {inst[i]}};
      return h;
    }
  } sa(f.rays), sb(f.rays);
  f.libs.embree->rtcIntersectNp(f.reference.scene(), &f.context, &sa.np, unsigned(n));
  f.libs.obvh->rtcIntersectNp(f.candidate.scene(), &f.context, &sb.np, unsigned(n));
  std::vector<RTCRayHit> na, nb;
  for (size_t i = 0; i < n; ++i) na.push_back(sa.at(i)), nb.push_back(sb.at(i));
  expectStreamAgrees(f, na, nb, ("rtcIntersectNp" + suffix).c_str());
}

TEST(CrossvalStreams, IntersectNMAndNp) {
  Fixture f;
  expectIntersectNMAndNpAgree(f);
}

TEST(CrossvalStreams, CoherentIntersectNMAndNp) {
  Fixture f;
  f.context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  expectIntersectNMAndNpAgree(f, " (coherent)");
}

void expectOccluded1MAgrees(Fixture& f, const char* name) {
  std::vector<RTCRay> a(f.rays.begin(), f.rays.begin() + 20000), b = a;
  f.libs.embree->rtcOccluded1M(f.reference.scene(), &f.context, a.data(), unsigned(a.size()), sizeof(RTCRay));
  f.libs.obvh->rtcOccluded1M(f.candidate.scene(), &f.context, b.data(), unsigned(b.size()), sizeof(RTCRay));
  CrossvalCounts counts;
  const float hit = -std::numeric_limits<float>::infinity();
  for (size_t i = 0; i < a.size(); ++i) judgeOcclusion(f.scene, f.rays[i], a[i].tfar == hit, b[i].tfar == hit, counts);
  std::printf("[crossval] %-34s %s\n", name, counts.summary().c_str());
  EXPECT_EQ(counts.mismatched, 0u) << counts.summary();
}

void expectOccluded1MNMAndNpAgree(Fixture& f, const std::string& suffix = "") {
  expectOccluded1MAgrees(f, ("rtcOccluded1M" + suffix).c_str());
  const float hit = -std::numeric_limits<float>::infinity();

  constexpr unsigned N = 4;
  const unsigned M = 5000;
  std::vector<RTCRayNt<N>> pa(M), pb;
  for (unsigned m = 0; m < M; ++m) {
    RTCRayHitNt<N> p;
    loadPacket<N>(p, f.rays, size_t(m) * N);
    pa[m] = p.ray;
  }
  pb = pa;
  f.libs.embree->rtcOccludedNM(f.reference.scene(), &f.context, reinterpret_cast<RTCRayN*>(pa.data()), N, M,
                               sizeof(RTCRayNt<N>));
  f.libs.obvh->rtcOccludedNM(f.candidate.scene(), &f.context, reinterpret_cast<RTCRayN*>(pb.data()), N, M,
                             sizeof(RTCRayNt<N>));
  CrossvalCounts nm;
  for (unsigned m = 0; m < M; ++m)
    for (unsigned i = 0; i < N; ++i)
      judgeOcclusion(f.scene, f.rays[size_t(m) * N + i], pa[m].tfar[i] == hit, pb[m].tfar[i] == hit, nm);
  std::printf("[crossval] %-34s %s\n", ("rtcOccludedNM (N=4)" + suffix).c_str(), nm.summary().c_str());
  EXPECT_EQ(nm.mismatched, 0u) << nm.summary();

  // Np: one array per member.
  const size_t n = 20000;
  struct Soa {
    std::vector<float> ox, oy, oz, tn, dx, dy, dz, time, tf;
    std::vector<unsigned> mask, id, flags;
    RTCRayNp np{};
    Soa(const std::vector<RTCRay>& rays, size_t count) {
      for (size_t i = 0; i < count; ++i) {
        const RTCRay& r = rays[i];
        ox.push_back(r.org_x), oy.push_back(r.org_y), oz.push_back(r.org_z), tn.push_back(r.tnear);
        dx.push_back(r.dir_x), dy.push_back(r.dir_y), dz.push_back(r.dir_z), time.push_back(0.f), tf.push_back(r.tfar);
        mask.push_back(r.mask), id.push_back(unsigned(i)), flags.push_back(0);
      }
      np = {ox.data(), oy.data(), oz.data(), tn.data(), dx.data(), dy.data(), dz.data(), time.data(), tf.data(),
            mask.data(), id.data(), flags.data()};
    }
  } sa(f.rays, n), sb(f.rays, n);
  f.libs.embree->rtcOccludedNp(f.reference.scene(), &f.context, &sa.np, unsigned(n));
  f.libs.obvh->rtcOccludedNp(f.candidate.scene(), &f.context, &sb.np, unsigned(n));
  CrossvalCounts np;
  for (size_t i = 0; i < n; ++i) judgeOcclusion(f.scene, f.rays[i], sa.tf[i] == hit, sb.tf[i] == hit, np);
  std::printf("[crossval] %-34s %s\n", ("rtcOccludedNp" + suffix).c_str(), np.summary().c_str());
  EXPECT_EQ(np.mismatched, 0u) << np.summary();
  size_t tfarDiffers = 0;
  for (size_t i = 0; i < n; ++i) tfarDiffers += (sa.tf[i] == hit) == (sb.tf[i] == hit) && sa.tf[i] != sb.tf[i];
  EXPECT_EQ(tfarDiffers, 0u) << "unoccluded rays must keep their tfar";
}

TEST(CrossvalStreams, Occluded1MNMAndNp) {
  Fixture f;
  expectOccluded1MNMAndNpAgree(f);
}

// Declared coherent, obvh traces 1M and Np streams as packets of consecutive rays (Embree too).
TEST(CrossvalStreams, CoherentOccluded1MNMAndNp) {
  Fixture f;
  f.context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  expectOccluded1MNMAndNpAgree(f, " (coherent)");
}

}  // namespace
}  // namespace obvh::test
