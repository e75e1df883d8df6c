// rtcIntersect4/8/16 and rtcOccluded4/8/16 take each lane's ray from Embree's SOA layout four lanes
// at a time (eight with AVX2, for packets of 8 and 16), and write hits back eight at a time on such
// CPUs. Every field must reach its own lane: each lane of a packet answers as the same ray
// through rtcIntersect1 / rtcOccluded1, with its own mask (ray masks on and off), time, segment
// and validity, and inactive lanes stay untouched. Streams of single rays declared coherent
// (rtcIntersect1M/1Mp, rtcOccluded1M/1Mp) are traced as packets of consecutive rays: each ray must
// answer as itself alone, whatever its place in a packet, its stride or a skipped (null) entry.
// The packet queries prefetch the memory after the packet: one that ends where the process's
// memory ends must answer as any other.
#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include <sys/mman.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <new>
#include <limits>
#include <random>
#include <vector>

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

class PacketLanes : public ::testing::TestWithParam<const char*> {
 protected:
  // Two horizontal grids of unit squares (z = 0 with geometry mask 1, z = 1 with mask 2), so that a
  // ray's mask and segment decide which one it hits.
  void SetUp() override {
    device = rtcNewDevice(GetParam());
    ASSERT_NE(device, nullptr);
    scene = rtcNewScene(device);
    for (unsigned layer = 0; layer < 2; ++layer) {
      RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
      constexpr unsigned kSide = 8;
      auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                   3 * sizeof(float), (kSide + 1) * (kSide + 1)));
      auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                     3 * sizeof(unsigned), 2 * kSide * kSide));
      for (unsigned y = 0; y <= kSide; ++y)
        for (unsigned x = 0; x <= kSide; ++x) {
          float* v = vertices + 3 * (y * (kSide + 1) + x);
          v[0] = float(x), v[1] = float(y), v[2] = float(layer);
        }
      for (unsigned y = 0; y < kSide; ++y)
        for (unsigned x = 0; x < kSide; ++x) {
          const unsigned a = y * (kSide + 1) + x, b = a + 1, c = a + kSide + 2, d = a + kSide + 1;
          const unsigned quad[6] = {a, b, c, a, c, d};
          std::memcpy(indices + 6 * (y * kSide + x), quad, sizeof quad);
        }
      rtcSetGeometryMask(geometry, 1u << layer);
      rtcCommitGeometry(geometry);
      rtcAttachGeometry(scene, geometry);
      rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(scene);
  }
  void TearDown() override {
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
  }

  // Rays down onto the grids from varied origins, with masks 0..3, empty and short segments and
  // distinct times (each field distinct per lane, so a lane reading another's shows).
  static RTCRay laneRay(std::mt19937& rng) {
    std::uniform_real_distribution<float> xy(0.1f, 7.9f), tilt(-0.2f, 0.2f);
    RTCRay ray{};
    ray.org_x = xy(rng), ray.org_y = xy(rng), ray.org_z = 3.f;
    ray.dir_x = tilt(rng), ray.dir_y = tilt(rng), ray.dir_z = -1.f;
    const unsigned kind = rng() % 6;
    ray.tnear = kind == 0 ? 2.5f : 0.f;                      // beyond the upper grid
    ray.tfar = kind == 1 ? 1.5f : kind == 2 ? -1.f : kInf;   // short of the lower grid; empty
    ray.time = float(rng() % 100) / 100.f;
    ray.mask = rng() % 4;
    ray.id = rng();
    return ray;
  }

  // Lane i of an RTCRay4/8/16 set to r (Embree's header has the reverse, rtcGetRayFromRayN).
  template <typename RayPacket>
  static void setLane(RayPacket& rays, int i, const RTCRay& r) {
    rays.org_x[i] = r.org_x, rays.org_y[i] = r.org_y, rays.org_z[i] = r.org_z;
    rays.dir_x[i] = r.dir_x, rays.dir_y[i] = r.dir_y, rays.dir_z[i] = r.dir_z;
    rays.tnear[i] = r.tnear, rays.tfar[i] = r.tfar, rays.time[i] = r.time;
    rays.mask[i] = r.mask, rays.id[i] = r.id, rays.flags[i] = 0;
  }

  // packet: where the packets lie, one after the other (the caller's storage).
  template <int W, typename PacketHit>
  void expectLanesAnswerAsSingleRays(void (*intersectW)(const int*, RTCScene, RTCIntersectContext*, PacketHit*),
                                     PacketHit& packet) {
    std::mt19937 rng(W);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    size_t hits = 0;
    for (int p = 0; p < 200; ++p) {
      alignas(64) int valid[W];
      std::vector<RTCRayHit> single(W);
      for (int i = 0; i < W; ++i) {
        valid[i] = rng() % 4 == 0 ? 0 : -1;
        single[i].ray = laneRay(rng);
        single[i].hit.geomID = RTC_INVALID_GEOMETRY_ID;
        setLane(packet.ray, i, single[i].ray);
        packet.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
      }
      intersectW(valid, scene, &context, &packet);
      for (int i = 0; i < W; ++i) {
        if (valid[i] != -1) {
          EXPECT_EQ(packet.ray.tfar[i], single[i].ray.tfar) << "inactive lane " << i << " changed";
          EXPECT_EQ(packet.hit.geomID[i], RTC_INVALID_GEOMETRY_ID);
          continue;
        }
        rtcIntersect1(scene, &context, &single[i]);
        EXPECT_EQ(packet.hit.geomID[i], single[i].hit.geomID) << "width " << W << " packet " << p << " lane " << i;
        EXPECT_EQ(packet.ray.tfar[i], single[i].ray.tfar) << "width " << W << " packet " << p << " lane " << i;
        if (single[i].hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        ++hits;
        EXPECT_EQ(packet.hit.primID[i], single[i].hit.primID);
        EXPECT_EQ(packet.hit.u[i], single[i].hit.u);
        EXPECT_EQ(packet.hit.v[i], single[i].hit.v);
      }
    }
    EXPECT_GT(hits, 100u * W / 4);
  }

  template <int W, typename Packet>
  void expectLanesOccludeAsSingleRays(void (*occludedW)(const int*, RTCScene, RTCIntersectContext*, Packet*),
                                      Packet& packet) {
    std::mt19937 rng(W + 100);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    size_t occluded = 0, open = 0;
    for (int p = 0; p < 200; ++p) {
      alignas(64) int valid[W];
      std::vector<RTCRay> single(W);
      for (int i = 0; i < W; ++i) {
        valid[i] = rng() % 4 == 0 ? 0 : -1;
        single[i] = laneRay(rng);
        setLane(packet, i, single[i]);
      }
      occludedW(valid, scene, &context, &packet);
      for (int i = 0; i < W; ++i) {
        if (valid[i] != -1) {
          EXPECT_EQ(packet.tfar[i], single[i].tfar) << "inactive lane " << i << " changed";
          continue;
        }
        rtcOccluded1(scene, &context, &single[i]);
        EXPECT_EQ(packet.tfar[i], single[i].tfar) << "width " << W << " packet " << p << " lane " << i;
        (single[i].tfar == -kInf ? occluded : open)++;
      }
    }
    EXPECT_GT(occluded, 50u * W / 4);
    EXPECT_GT(open, 50u * W / 4);
  }

  // A coherent stream of `count` rays (not a multiple of the packet size), laid out with a stride
  // larger than RTCRayHit and, for 1Mp, one entry in seven null: each ray answers as rtcIntersect1
  // answers it alone, and the padding between the rays stays untouched.
  void expectCoherentStreamAnswersAsSingleRays(unsigned count) {
    std::mt19937 rng(count);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    struct Padded {
      RTCRayHit rayhit;
      unsigned guard[5];
    };
    std::vector<Padded> stream(count), pointed(count);
    std::vector<RTCRayHit> single(count);
    std::vector<RTCRayHit*> pointers(count);
    for (unsigned i = 0; i < count; ++i) {
      single[i].ray = laneRay(rng);
      single[i].hit.geomID = RTC_INVALID_GEOMETRY_ID;
      stream[i].rayhit = pointed[i].rayhit = single[i];
      for (unsigned& g : stream[i].guard) g = 0xC0FFEEu;
      pointers[i] = i % 7 == 3 ? nullptr : &pointed[i].rayhit;
    }
    rtcIntersect1M(scene, &context, &stream[0].rayhit, count, sizeof(Padded));
    rtcIntersect1Mp(scene, &context, pointers.data(), count);
    size_t hits = 0;
    for (unsigned i = 0; i < count; ++i) {
      RTCRayHit alone = single[i];
      rtcIntersect1(scene, &context, &alone);
      for (unsigned g : stream[i].guard) EXPECT_EQ(g, 0xC0FFEEu) << "padding behind ray " << i;
      EXPECT_EQ(stream[i].rayhit.hit.geomID, alone.hit.geomID) << "1M ray " << i;
      EXPECT_EQ(stream[i].rayhit.ray.tfar, alone.ray.tfar) << "1M ray " << i;
      const RTCRayHit& viaPointer = pointers[i] ? pointed[i].rayhit : alone;
      if (!pointers[i]) {
        EXPECT_EQ(std::memcmp(&pointed[i].rayhit, &single[i], sizeof(RTCRayHit)), 0) << "null entry " << i << " traced";
      }
      EXPECT_EQ(viaPointer.hit.geomID, alone.hit.geomID) << "1Mp ray " << i;
      EXPECT_EQ(viaPointer.ray.tfar, alone.ray.tfar) << "1Mp ray " << i;
      if (alone.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
      ++hits;
      EXPECT_EQ(stream[i].rayhit.hit.primID, alone.hit.primID) << "1M ray " << i;
      EXPECT_EQ(stream[i].rayhit.hit.u, alone.hit.u) << "1M ray " << i;
      EXPECT_EQ(stream[i].rayhit.hit.v, alone.hit.v) << "1M ray " << i;
      EXPECT_EQ(stream[i].rayhit.hit.Ng_z, alone.hit.Ng_z) << "1M ray " << i;
      EXPECT_EQ(viaPointer.hit.primID, alone.hit.primID) << "1Mp ray " << i;
      EXPECT_EQ(viaPointer.hit.u, alone.hit.u) << "1Mp ray " << i;
    }
    EXPECT_GT(hits, count / 4);
  }

  void expectCoherentStreamOccludesAsSingleRays(unsigned count) {
    std::mt19937 rng(count + 1);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    std::vector<RTCRay> stream(count), single(count);
    std::vector<RTCRay> pointed(count);
    std::vector<RTCRay*> pointers(count);
    for (unsigned i = 0; i < count; ++i) {
      single[i] = stream[i] = pointed[i] = laneRay(rng);
      pointers[i] = i % 5 == 2 ? nullptr : &pointed[i];
    }
    rtcOccluded1M(scene, &context, stream.data(), count, sizeof(RTCRay));
    rtcOccluded1Mp(scene, &context, pointers.data(), count);
    size_t occluded = 0, open = 0;
    for (unsigned i = 0; i < count; ++i) {
      const float before = single[i].tfar;
      rtcOccluded1(scene, &context, &single[i]);
      EXPECT_EQ(stream[i].tfar, single[i].tfar) << "1M ray " << i;
      EXPECT_EQ(pointed[i].tfar, pointers[i] ? single[i].tfar : before) << "1Mp ray " << i;
      (single[i].tfar == -kInf ? occluded : open)++;
    }
    EXPECT_GT(occluded, count / 8);
    EXPECT_GT(open, count / 8);
  }

  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
};

TEST_P(PacketLanes, IntersectLanesAnswerAsSingleRays) {
  RTCRayHit4 packet4;
  RTCRayHit8 packet8;
  RTCRayHit16 packet16;
  expectLanesAnswerAsSingleRays<4>(rtcIntersect4, packet4);
  expectLanesAnswerAsSingleRays<8>(rtcIntersect8, packet8);
  expectLanesAnswerAsSingleRays<16>(rtcIntersect16, packet16);
}

TEST_P(PacketLanes, OccludedLanesAnswerAsSingleRays) {
  RTCRay4 packet4;
  RTCRay8 packet8;
  RTCRay16 packet16;
  expectLanesOccludeAsSingleRays<4>(rtcOccluded4, packet4);
  expectLanesOccludeAsSingleRays<8>(rtcOccluded8, packet8);
  expectLanesOccludeAsSingleRays<16>(rtcOccluded16, packet16);
}

// Two pages of their own, the second one closed to every access: a packet placed at the end of the
// first ends where the memory the process may touch ends.
class GuardedPage {
 public:
  GuardedPage() : size_(size_t(sysconf(_SC_PAGESIZE))) {
    void* mapping = mmap(nullptr, 2 * size_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (mapping == MAP_FAILED) return;
    base_ = static_cast<char*>(mapping);
    if (mprotect(base_ + size_, size_, PROT_NONE) != 0) munmap(base_, 2 * size_), base_ = nullptr;
  }
  ~GuardedPage() {
    if (base_) munmap(base_, 2 * size_);
  }
  bool usable() const { return base_ != nullptr; }
  // Embree's packet types' sizes are multiples of their alignment (and of 64 bytes).
  template <typename Packet>
  Packet& packetAtEnd() const {
    return *::new (base_ + size_ - sizeof(Packet)) Packet;
  }

 private:
  size_t size_;
  char* base_ = nullptr;
};

// The packet queries prefetch the memory after the application's packet, where an array of packets
// keeps the next one (query_dispatch.cpp): a packet that the process's memory ends with answers
// as any other.
TEST_P(PacketLanes, PacketsEndingWhereMemoryEndsAnswerAsSingleRays) {
  const GuardedPage page;
  ASSERT_TRUE(page.usable());
  expectLanesAnswerAsSingleRays<4>(rtcIntersect4, page.packetAtEnd<RTCRayHit4>());
  expectLanesAnswerAsSingleRays<8>(rtcIntersect8, page.packetAtEnd<RTCRayHit8>());
  expectLanesAnswerAsSingleRays<16>(rtcIntersect16, page.packetAtEnd<RTCRayHit16>());
  expectLanesOccludeAsSingleRays<4>(rtcOccluded4, page.packetAtEnd<RTCRay4>());
  expectLanesOccludeAsSingleRays<8>(rtcOccluded8, page.packetAtEnd<RTCRay8>());
  expectLanesOccludeAsSingleRays<16>(rtcOccluded16, page.packetAtEnd<RTCRay16>());
}

TEST_P(PacketLanes, CoherentStreamsAnswerAsSingleRays) {
  expectCoherentStreamAnswersAsSingleRays(1003);
  expectCoherentStreamOccludesAsSingleRays(1003);
}

// Coherent streams whose rays' packets miss the scene's box whole, in part, or along its faces:
// packets of eight go through the structure's box first (the packet gate) where the scene's rays
// may go straight to the kernels, and each ray must still answer as rtcIntersect1 answers it alone
// (a ray that misses keeps its tfar and hit). Rays along the axes start outside, on and inside
// the box's planes; others start beside the box, carry NaN origins or directions, or negative,
// -0 or empty segments.
TEST_P(PacketLanes, CoherentStreamsTurnAwayOnlyRaysThatMiss) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> inside(0.1f, 7.9f), beside(8.5f, 20.f), tilt(-0.2f, 0.2f);
  // The box's planes and just beyond them, for rays straight down (x and y are axes they do not
  // move along) and rays along x (y and z).
  const float edges[] = {0.f, 8.f, std::nextafter(0.f, -1.f), std::nextafter(8.f, 9.f), -0.f, 4.f};
  constexpr unsigned kPackets = 160;
  std::vector<RTCRayHit> single(kPackets * 8);
  for (unsigned i = 0; i < single.size(); ++i) {
    const unsigned kind = (i / 8) % 5, lane = i % 8;
    RTCRay ray{};
    ray.org_x = inside(rng), ray.org_y = inside(rng), ray.org_z = 3.f;
    ray.dir_x = tilt(rng), ray.dir_y = tilt(rng), ray.dir_z = -1.f;
    ray.tfar = kInf;
    ray.mask = 3;
    if (kind == 0 || (kind == 1 && lane % 2 == 0)) {  // beside the box: the whole packet, or half of it
      ray.org_x = beside(rng);
      ray.dir_x = std::abs(ray.dir_x);
    } else if (kind == 2) {  // straight down, from on, inside and beyond the box's planes
      ray.org_x = edges[rng() % 6], ray.org_y = edges[rng() % 6];
      ray.dir_x = lane % 2 ? 0.f : -0.f, ray.dir_y = 0.f;
    } else if (kind == 3) {  // along x, at heights on, inside and beyond the box's z planes
      const float heights[] = {0.f, 1.f, 0.5f, std::nextafter(1.f, 2.f), -0.f, 2.f};
      ray.org_x = lane % 2 ? -3.f : 11.f, ray.org_z = heights[rng() % 6];
      ray.dir_x = lane % 2 ? 1.f : -1.f, ray.dir_y = 0.f, ray.dir_z = 0.f;
    }
    switch (rng() % 8) {  // odd rays anywhere in a packet
      case 0: ray.tnear = -1.f; break;
      case 1: ray.tnear = -0.f; break;
      case 2: ray.tnear = 5.f, ray.tfar = 2.f; break;  // empty
      case 3: if (kind == 4) ray.org_y = nan; break;
      case 4: if (kind == 4) ray.dir_z = nan; break;
      default: break;
    }
    single[i].ray = ray;
    single[i].hit.geomID = single[i].hit.primID = RTC_INVALID_GEOMETRY_ID;
  }
  std::vector<RTCRayHit> stream = single, pointed = single;
  std::vector<RTCRayHit*> pointers;
  for (RTCRayHit& r : pointed) pointers.push_back(&r);
  rtcIntersect1M(scene, &context, stream.data(), unsigned(stream.size()), sizeof(RTCRayHit));
  rtcIntersect1Mp(scene, &context, pointers.data(), unsigned(pointers.size()));
  size_t hits = 0, misses = 0;
  for (size_t i = 0; i < single.size(); ++i) {
    RTCRayHit alone = single[i];
    rtcIntersect1(scene, &context, &alone);
    for (const RTCRayHit* traced : {&stream[i], &pointed[i]}) {
      const char* how = traced == &stream[i] ? "1M" : "1Mp";
      EXPECT_EQ(traced->hit.geomID, alone.hit.geomID) << how << " ray " << i;
      EXPECT_EQ(std::memcmp(&traced->ray.tfar, &alone.ray.tfar, sizeof(float)), 0) << how << " ray " << i;
      if (alone.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
      EXPECT_EQ(traced->hit.primID, alone.hit.primID) << how << " ray " << i;
      EXPECT_EQ(traced->hit.u, alone.hit.u) << how << " ray " << i;
      EXPECT_EQ(traced->hit.v, alone.hit.v) << how << " ray " << i;
    }
    (alone.hit.geomID == RTC_INVALID_GEOMETRY_ID ? misses : hits)++;
  }
  EXPECT_GT(hits, single.size() / 4);
  EXPECT_GT(misses, single.size() / 4);
}

INSTANTIATE_TEST_SUITE_P(RayMasks, PacketLanes,
                         ::testing::Values("", "ray_mask=off", "accel=bvh4", "accel=obb,obb_packets=on",
                                           "accel=hybrid,obb_packets=on,ray_mask=off"));

}  // namespace
