/* Embree 3 as the hardware anchor of spectrace's BVH (host/benches/scaling.rs runs it).
 *
 * Reads one binary file (little endian): u32 vertex count V, u32 triangle count T, V×3 f32
 * positions, T×3 u32 indices, u32 ray count R, R×6 f32 rays (origin, direction). Builds an
 * Embree scene (one triangle geometry, default build quality), then traces every ray with
 * rtcIntersect1 (single rays, closest hit, t in [0, ∞)) on one thread and on two threads, best of
 * three runs each. Prints one line: "build_s <s> hits <n> mrays_1 <M/s> mrays_2 <M/s>".
 *
 * EMBREE_RAYS_CONFIG=<string> replaces the device configuration "threads=2", e.g.
 * "threads=2,verbose=2" (Embree then reports the ISA it selected, its builder and the BVH's
 * statistics on stdout before the harness's line) or "threads=2,isa=avx2" (to compare ISAs).
 *
 * Build: cc -O2 embree_rays.c -lembree3 -lpthread -o embree_rays   (Debian: libembree-dev)
 */
#include <embree3/rtcore.h>
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static RTCScene scene;
static float *rays;
static uint32_t nrays;

typedef struct { uint32_t first, last; uint64_t hits; } Job;

static void *trace(void *arg) {
    Job *job = (Job *)arg;
    struct RTCIntersectContext ctx;
    uint64_t hits = 0;
    for (uint32_t i = job->first; i < job->last; i++) {
        rtcInitIntersectContext(&ctx);
        struct RTCRayHit rh;
        const float *r = rays + 6 * (size_t)i;
        rh.ray.org_x = r[0]; rh.ray.org_y = r[1]; rh.ray.org_z = r[2];
        rh.ray.dir_x = r[3]; rh.ray.dir_y = r[4]; rh.ray.dir_z = r[5];
        rh.ray.tnear = 0.0f; rh.ray.tfar = INFINITY; rh.ray.time = 0.0f;
        rh.ray.mask = 0xFFFFFFFF; rh.ray.id = i; rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ctx, &rh);
        hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
    job->hits = hits;
    return NULL;
}

static double run(int threads, uint64_t *hits) {
    double best = 1e30;
    for (int k = 0; k < 3; k++) {
        pthread_t tid[2];
        Job jobs[2];
        double t0 = now();
        for (int j = 0; j < threads; j++) {
            jobs[j].first = (uint32_t)((uint64_t)nrays * j / threads);
            jobs[j].last = (uint32_t)((uint64_t)nrays * (j + 1) / threads);
            pthread_create(&tid[j], NULL, trace, &jobs[j]);
        }
        *hits = 0;
        for (int j = 0; j < threads; j++) {
            pthread_join(tid[j], NULL);
            *hits += jobs[j].hits;
        }
        double t = now() - t0;
        if (t < best) best = t;
    }
    return best;
}

static void read_exact(FILE *f, void *p, size_t n) {
    if (fread(p, 1, n, f) != n) {
        fprintf(stderr, "embree_rays: input file too short\n");
        exit(2);
    }
}

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: embree_rays FILE\n");
        return 2;
    }
    FILE *f = fopen(argv[1], "rb");
    if (!f) {
        perror(argv[1]);
        return 2;
    }
    uint32_t nv, nt;
    read_exact(f, &nv, 4);
    read_exact(f, &nt, 4);
    float *v = malloc((size_t)nv * 12);
    uint32_t *idx = malloc((size_t)nt * 12);
    read_exact(f, v, (size_t)nv * 12);
    read_exact(f, idx, (size_t)nt * 12);
    read_exact(f, &nrays, 4);
    rays = malloc((size_t)nrays * 24);
    read_exact(f, rays, (size_t)nrays * 24);
    fclose(f);

    const char *config = getenv("EMBREE_RAYS_CONFIG");
    RTCDevice device = rtcNewDevice(config ? config : "threads=2");
    double t0 = now();
    scene = rtcNewScene(device);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *vb = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, nv);
    uint32_t *ib = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, nt);
    for (size_t i = 0; i < (size_t)nv * 3; i++) vb[i] = v[i];
    for (size_t i = 0; i < (size_t)nt * 3; i++) ib[i] = idx[i];
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    double build = now() - t0;

    uint64_t hits1, hits2;
    double s1 = run(1, &hits1);
    double s2 = run(2, &hits2);
    printf("build_s %.4f hits %llu mrays_1 %.4f mrays_2 %.4f\n", build, (unsigned long long)hits1,
           nrays / s1 / 1e6, nrays / s2 / 1e6);
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    return 0;
}
