// The GPU broad phase's kernels (compiled at run time by NVRTC; see mod.rs for the plan).
//
// Boxes are 6 doubles each, min x y z then max x y z. A box is "valid" when all six are finite
// and min <= max on every axis; invalid boxes overlap nothing. Pairs are reported as lists: box
// i's list holds every j > i whose box overlaps box i's (touching counts), sorted.

typedef unsigned int u32;
typedef unsigned long long u64;

#define EXP_BINS 2048
#define NONE 0xFFFFFFFFu
#define OVERSIZE 0xFFFFFFFEu
#define SCAN_THREADS 1024
#define SCAN_ITEMS 4
#define SCAN_TILE (SCAN_THREADS * SCAN_ITEMS)

// A double's bits mapped to an unsigned integer of the same order.
__device__ __forceinline__ u64 ordered(double x) {
    long long b = __double_as_longlong(x);
    return b >= 0 ? ((u64)b | 0x8000000000000000ull) : ~(u64)b;
}

__device__ __forceinline__ bool valid(const double* b) {
    return isfinite(b[0]) && isfinite(b[1]) && isfinite(b[2]) && isfinite(b[3]) &&
           isfinite(b[4]) && isfinite(b[5]) && b[0] <= b[3] && b[1] <= b[4] && b[2] <= b[5];
}

__device__ __forceinline__ double width(const double* b) {
    return fmax(fmax(b[3] - b[0], b[4] - b[1]), b[5] - b[2]);
}

__device__ __forceinline__ bool overlap(const double* a, const double* b) {
    return a[0] <= b[3] && b[0] <= a[3] && a[1] <= b[4] && b[1] <= a[4] && a[2] <= b[5] &&
           b[2] <= a[5];
}

// The extent of the valid boxes' low corners (ordered bits: min x y z, max x y z), and per
// exponent of a box's largest width, the count of valid boxes and their largest width (bits).
extern "C" __global__ void stats(const double* __restrict__ boxes, u32 n, u64* bounds,
                                 u32* hist, u64* bin_max) {
    __shared__ u32 s_hist[EXP_BINS];
    __shared__ u64 s_max[EXP_BINS];
    __shared__ u64 s_bounds[6];
    for (u32 k = threadIdx.x; k < EXP_BINS; k += blockDim.x) {
        s_hist[k] = 0;
        s_max[k] = 0;
    }
    if (threadIdx.x < 6) s_bounds[threadIdx.x] = threadIdx.x < 3 ? ~0ull : 0ull;
    __syncthreads();
    u64 lo[3] = {~0ull, ~0ull, ~0ull};
    u64 hi[3] = {0ull, 0ull, 0ull};
    for (u32 i = blockIdx.x * blockDim.x + threadIdx.x; i < n; i += gridDim.x * blockDim.x) {
        const double* b = boxes + 6ull * i;
        if (!valid(b)) continue;
        for (int k = 0; k < 3; ++k) {
            u64 o = ordered(b[k]);
            lo[k] = o < lo[k] ? o : lo[k];
            hi[k] = o > hi[k] ? o : hi[k];
        }
        double w = width(b);
        u64 bits = (u64)__double_as_longlong(w);  // w >= 0: the bits order as the values
        u32 e = (u32)(bits >> 52) & 0x7FF;
        atomicAdd(&s_hist[e], 1u);
        atomicMax(&s_max[e], bits);
    }
    for (int k = 0; k < 3; ++k) {
        atomicMin(&s_bounds[k], lo[k]);
        atomicMax(&s_bounds[3 + k], hi[k]);
    }
    __syncthreads();
    for (u32 k = threadIdx.x; k < EXP_BINS; k += blockDim.x) {
        if (s_hist[k] != 0) {
            atomicAdd(&hist[k], s_hist[k]);
            atomicMax(&bin_max[k], s_max[k]);
        }
    }
    if (threadIdx.x < 3) atomicMin(&bounds[threadIdx.x], s_bounds[threadIdx.x]);
    else if (threadIdx.x < 6) atomicMax(&bounds[threadIdx.x], s_bounds[threadIdx.x]);
}

__device__ __forceinline__ u32 cell_coord(double v, double origin, double size, u32 count) {
    double q = floor((v - origin) / size);
    if (!(q > 0.0)) return 0;
    if (q >= (double)(count - 1)) return count - 1;
    return (u32)q;
}

struct Grid {
    double ox, oy, oz, size;
    u32 nx, ny, nz;
};

__device__ __forceinline__ void cell_of_corner(const double* b, const Grid& g, u32* c) {
    c[0] = cell_coord(b[0], g.ox, g.size, g.nx);
    c[1] = cell_coord(b[1], g.oy, g.size, g.ny);
    c[2] = cell_coord(b[2], g.oz, g.size, g.nz);
}

// Each valid box of width at most `wmax` into the cell of its low corner (counted); wider ones
// into the oversize list; invalid ones nowhere.
extern "C" __global__ void assign(const double* __restrict__ boxes, u32 n, double ox, double oy,
                                  double oz, double size, u32 nx, u32 ny, u32 nz, double wmax,
                                  u32* cell_of, u32* cell_count, u32* over_list, u32* over_n) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const double* b = boxes + 6ull * i;
    if (!valid(b)) {
        cell_of[i] = NONE;
        return;
    }
    if (width(b) > wmax) {
        cell_of[i] = OVERSIZE;
        over_list[atomicAdd(over_n, 1u)] = i;
        return;
    }
    Grid g = {ox, oy, oz, size, nx, ny, nz};
    u32 c[3];
    cell_of_corner(b, g, c);
    u32 cell = (c[0] * ny + c[1]) * nz + c[2];
    cell_of[i] = cell;
    atomicAdd(&cell_count[cell], 1u);
}

// The boxes in cell order (a counting sort: the order inside a cell is whatever the atomics
// give; nothing downstream depends on it).
extern "C" __global__ void scatter(const double* __restrict__ boxes, u32 n,
                                   const u32* __restrict__ cell_of,
                                   const u32* __restrict__ cell_start, u32* cell_fill,
                                   u32* sorted_id, double* sorted_boxes) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    u32 c = cell_of[i];
    if (c >= OVERSIZE) return;
    u32 p = cell_start[c] + atomicAdd(&cell_fill[c], 1u);
    sorted_id[p] = i;
    for (int k = 0; k < 6; ++k) sorted_boxes[6ull * p + k] = boxes[6ull * i + k];
}

// A regular box against the boxes of the 27 cells around its own and against every oversize
// box: counts (write = 0) or writes its list, sorted (write = 1). Two overlapping regular boxes
// have low corners less than a cell apart on every axis, so their cells are neighbours.
extern "C" __global__ void near_pairs(const double* __restrict__ sorted_boxes,
                                      const u32* __restrict__ sorted_id,
                                      const u32* __restrict__ cell_start, u32 cells, double ox,
                                      double oy, double oz, double size, u32 nx, u32 ny, u32 nz,
                                      const double* __restrict__ boxes,
                                      const u32* __restrict__ over_list, u32 over_n, u32* count,
                                      const u32* __restrict__ offset, u32* partners, int write) {
    u32 p = blockIdx.x * blockDim.x + threadIdx.x;
    if (p >= cell_start[cells]) return;
    u32 i = sorted_id[p];
    double a[6];
    for (int k = 0; k < 6; ++k) a[k] = sorted_boxes[6ull * p + k];
    Grid g = {ox, oy, oz, size, nx, ny, nz};
    u32 c[3];
    cell_of_corner(a, g, c);
    u32 x0 = c[0] > 0 ? c[0] - 1 : 0, x1 = c[0] + 1 < nx ? c[0] + 1 : nx - 1;
    u32 y0 = c[1] > 0 ? c[1] - 1 : 0, y1 = c[1] + 1 < ny ? c[1] + 1 : ny - 1;
    u32 z0 = c[2] > 0 ? c[2] - 1 : 0, z1 = c[2] + 1 < nz ? c[2] + 1 : nz - 1;
    u32 base = write ? offset[i] : 0;
    u32 found = 0;
    for (u32 x = x0; x <= x1; ++x) {
        for (u32 y = y0; y <= y1; ++y) {
            u32 row = (x * ny + y) * nz;
            u32 q0 = cell_start[row + z0], q1 = cell_start[row + z1 + 1];
            for (u32 q = q0; q < q1; ++q) {
                u32 j = sorted_id[q];
                if (j > i && overlap(a, sorted_boxes + 6ull * q)) {
                    if (write) partners[base + found] = j;
                    ++found;
                }
            }
        }
    }
    for (u32 t = 0; t < over_n; ++t) {
        u32 j = over_list[t];
        if (j > i && overlap(a, boxes + 6ull * j)) {
            if (write) partners[base + found] = j;
            ++found;
        }
    }
    if (!write) {
        count[i] = found;
        return;
    }
    // The list in index order (lists are short: insertion sort).
    u32* list = partners + base;
    for (u32 s = 1; s < found; ++s) {
        u32 v = list[s];
        u32 r = s;
        while (r > 0 && list[r - 1] > v) {
            list[r] = list[r - 1];
            --r;
        }
        list[r] = v;
    }
}

// One block per oversize box: every valid box after it, in index order, tested; counts or
// writes its list (in order: a block-wide prefix over each chunk of candidates).
extern "C" __global__ void far_pairs(const double* __restrict__ boxes, u32 n,
                                     const u32* __restrict__ over_list, u32* count,
                                     const u32* __restrict__ offset, u32* partners, int write) {
    __shared__ u32 warp_total[32];
    __shared__ u32 running;
    u32 o = over_list[blockIdx.x];
    double a[6];
    for (int k = 0; k < 6; ++k) a[k] = boxes[6ull * o + k];
    u32 lane = threadIdx.x & 31, warp = threadIdx.x >> 5, warps = (blockDim.x + 31) >> 5;
    if (threadIdx.x == 0) running = 0;
    __syncthreads();
    for (u32 chunk = o + 1; chunk < n; chunk += blockDim.x) {
        u32 j = chunk + threadIdx.x;
        bool hit = false;
        if (j < n) {
            const double* b = boxes + 6ull * j;
            hit = valid(b) && overlap(a, b);
        }
        u32 ballot = __ballot_sync(0xFFFFFFFFu, hit);
        if (lane == 0) warp_total[warp] = __popc(ballot);
        __syncthreads();
        u32 before = running;
        for (u32 w = 0; w < warp; ++w) before += warp_total[w];
        if (write && hit) partners[offset[o] + before + __popc(ballot & ((1u << lane) - 1u))] = j;
        __syncthreads();
        if (threadIdx.x == 0) {
            u32 total = 0;
            for (u32 w = 0; w < warps; ++w) total += warp_total[w];
            running += total;
        }
        __syncthreads();
    }
    if (!write && threadIdx.x == 0) count[o] = running;
}

// Exclusive prefix sum of `n` values in place, one tile of SCAN_TILE per block; each tile's
// total to `tile_sums` (scanned next, then added back by `scan_add`).
extern "C" __global__ void scan_tiles(u32* values, u32 n, u32* tile_sums) {
    __shared__ u32 warp_sums[32];
    u32 base = blockIdx.x * SCAN_TILE + threadIdx.x * SCAN_ITEMS;
    u32 v[SCAN_ITEMS];
    u32 s = 0;
    for (int k = 0; k < SCAN_ITEMS; ++k) {
        v[k] = base + k < n ? values[base + k] : 0;
        s += v[k];
    }
    u32 lane = threadIdx.x & 31, warp = threadIdx.x >> 5;
    u32 x = s;
    for (u32 off = 1; off < 32; off <<= 1) {
        u32 y = __shfl_up_sync(0xFFFFFFFFu, x, off);
        if (lane >= off) x += y;
    }
    if (lane == 31) warp_sums[warp] = x;
    __syncthreads();
    if (warp == 0) {
        u32 w = warp_sums[lane];
        for (u32 off = 1; off < 32; off <<= 1) {
            u32 y = __shfl_up_sync(0xFFFFFFFFu, w, off);
            if (lane >= off) w += y;
        }
        warp_sums[lane] = w;
    }
    __syncthreads();
    u32 run = x - s + (warp > 0 ? warp_sums[warp - 1] : 0);
    for (int k = 0; k < SCAN_ITEMS; ++k) {
        if (base + k < n) values[base + k] = run;
        run += v[k];
    }
    if (threadIdx.x == SCAN_THREADS - 1) tile_sums[blockIdx.x] = run;
}

extern "C" __global__ void scan_add(u32* values, u32 n, const u32* __restrict__ tile_offsets) {
    u32 base = blockIdx.x * SCAN_TILE + threadIdx.x * SCAN_ITEMS;
    u32 add = tile_offsets[blockIdx.x];
    for (int k = 0; k < SCAN_ITEMS; ++k) {
        if (base + k < n) values[base + k] += add;
    }
}
