// Side-by-side reference for `glint bench rays`: the same OBJ, the same
// camera convention (README, "Conventions": up +y, one ray through each pixel
// centre, no jitter), primary rays traced with Intel Embree 4 (rtcIntersect1,
// incoherent single rays as glint traces them, one thread per core). Prints build ms and primary Mrays/s as key=value
// lines and writes the hit distance along the unit direction (inf on a
// miss) as a one-channel PFM ("Pf"), to compare with glint's --hitdist.
//
// Embree 4 comes from tools/embree/fetch (the library of a PyPI wheel and the
// API headers of a crate); tools/embree/run builds this against it:
//   g++ -O2 -std=c++17 -I PREFIX/include bench_embree.cpp -L PREFIX/lib \
//       -lembree4 -Wl,-rpath,PREFIX/lib -lpthread -o bench_embree
//   bench_embree FILE.obj W H ox oy oz tx ty tz vfov_deg RUNS OUT.pfm
#include <embree4/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

struct V3 { float x, y, z; };
static V3 sub(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
static V3 add(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
static V3 mul(V3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
static V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
static V3 norm(V3 a) { float l = std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z); return mul(a, 1.0f / l); }

// The headers are Embree 4.2's; from 4.3 on, a library built with instance
// arrays (the default) also writes RTCHit::instPrimID after instID, past the
// end of 4.2's RTCRayHit. The padding keeps that write inside our storage.
struct alignas(16) PaddedRayHit {
    RTCRayHit rh;
    unsigned char spare[32];
};

static double now_ms() {
    using namespace std::chrono;
    return duration<double, std::milli>(steady_clock::now().time_since_epoch()).count();
}

int main(int argc, char** argv) {
    if (argc != 13) {
        std::fprintf(stderr, "usage: %s FILE.obj W H ox oy oz tx ty tz vfov_deg RUNS OUT.pfm\n", argv[0]);
        return 2;
    }
    const int W = std::atoi(argv[2]), H = std::atoi(argv[3]);
    V3 pos{std::strtof(argv[4], nullptr), std::strtof(argv[5], nullptr), std::strtof(argv[6], nullptr)};
    V3 tgt{std::strtof(argv[7], nullptr), std::strtof(argv[8], nullptr), std::strtof(argv[9], nullptr)};
    const float vfov = std::strtof(argv[10], nullptr);
    const int runs = std::max(1, std::atoi(argv[11]));

    // OBJ: positions and faces (v, v/t, v//n, v/t/n; polygons fanned).
    std::ifstream in(argv[1]);
    if (!in) { std::fprintf(stderr, "cannot open %s\n", argv[1]); return 2; }
    std::vector<float> verts;
    std::vector<unsigned> tris;
    std::string line;
    while (std::getline(in, line)) {
        if (line.size() < 2) continue;
        if (line[0] == 'v' && line[1] == ' ') {
            std::istringstream s(line.substr(2));
            float x, y, z; s >> x >> y >> z;
            verts.insert(verts.end(), {x, y, z});
        } else if (line[0] == 'f' && line[1] == ' ') {
            std::istringstream s(line.substr(2));
            std::string tok; std::vector<long> idx;
            while (s >> tok) {
                long i = std::atol(tok.c_str());
                idx.push_back(i > 0 ? i - 1 : long(verts.size() / 3) + i);
            }
            for (size_t k = 1; k + 1 < idx.size(); k++) tris.insert(tris.end(), {unsigned(idx[0]), unsigned(idx[k]), unsigned(idx[k + 1])});
        }
    }
    const size_t nv = verts.size() / 3, nt = tris.size() / 3;

    RTCDevice device = rtcNewDevice(nullptr);
    if (!device) { std::fprintf(stderr, "rtcNewDevice failed (error %d)\n", int(rtcGetDeviceError(nullptr))); return 2; }
    // The library's own version, not the headers'.
    const long version = long(rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION));
    double t0 = now_ms();
    RTCScene scene = rtcNewScene(device);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float* vb = (float*)rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv);
    unsigned* ib = (unsigned*)rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nt);
    std::copy(verts.begin(), verts.end(), vb);
    std::copy(tris.begin(), tris.end(), ib);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    const double build_ms = now_ms() - t0;

    V3 fwd = norm(sub(tgt, pos));
    V3 right = norm(cross(fwd, V3{0, 1, 0}));
    V3 up = cross(right, fwd);
    const float th = std::tan(vfov * 3.14159265358979f / 360.0f), aspect = float(W) / float(H);
    std::vector<float> dist(size_t(W) * H);
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    auto trace_rows = [&](unsigned first) {
        for (int y = first; y < H; y += threads) {
            for (int x = 0; x < W; x++) {
                float sx = (2.0f * (x + 0.5f) / W - 1.0f) * aspect * th;
                float sy = (1.0f - 2.0f * (y + 0.5f) / H) * th;
                V3 d = norm(add(add(fwd, mul(right, sx)), mul(up, sy)));
                PaddedRayHit padded{};
                RTCRayHit& rh = padded.rh;
                rh.ray.org_x = pos.x; rh.ray.org_y = pos.y; rh.ray.org_z = pos.z;
                rh.ray.dir_x = d.x; rh.ray.dir_y = d.y; rh.ray.dir_z = d.z;
                rh.ray.tnear = 0.0f; rh.ray.tfar = std::numeric_limits<float>::infinity();
                rh.ray.mask = 0xffffffff;
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(scene, &rh);
                dist[size_t(y) * W + x] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? std::numeric_limits<float>::infinity() : rh.ray.tfar;
            }
        }
    };
    std::vector<double> times;
    for (int r = 0; r < runs + 1; r++) {  // the first run warms up
        double s = now_ms();
        std::vector<std::thread> pool;
        for (unsigned t = 0; t < threads; t++) pool.emplace_back(trace_rows, t);
        for (auto& t : pool) t.join();
        if (r > 0) times.push_back(now_ms() - s);
    }
    std::sort(times.begin(), times.end());
    const double ms = times[times.size() / 2];
    std::printf("embree_version=%ld.%ld.%ld\n", version / 10000, version / 100 % 100, version % 100);
    std::printf("threads=%u\n", threads);
    std::printf("triangles=%zu\n", nt);
    std::printf("embree_build_ms=%.1f\n", build_ms);
    std::printf("primary_ms=%.3f\n", ms);
    std::printf("primary_mrays_per_s=%.2f\n", double(W) * H / (ms * 1e3));

    FILE* f = std::fopen(argv[12], "wb");
    if (!f) { std::fprintf(stderr, "cannot write %s\n", argv[12]); return 2; }
    std::fprintf(f, "Pf\n%d %d\n-1.0\n", W, H);
    for (int y = H - 1; y >= 0; y--) std::fwrite(&dist[size_t(y) * W], sizeof(float), W, f);
    std::fclose(f);
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    return 0;
}
