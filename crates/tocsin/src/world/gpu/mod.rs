//! The broad phase on a CUDA GPU: the same pairs as [`super::broad::sweep_and_prune`], in the
//! same order (feature `cuda`).
//!
//! The crate loads CUDA at run time (cudarc, dynamic loading): it builds and runs without CUDA,
//! and [`GpuBroadPhase::new`] answers an error where no driver, no NVRTC or no device is found.
//! The kernels are CUDA C (`kernels.cu`), compiled by NVRTC once per [`GpuBroadPhase`]. The CPU
//! path stays the reference: the tests compare the two pair for pair.
//!
//! The plan. A GPU sorts badly in cells of varying size, so where the CPU sorts each cell of a
//! two-axis grid and sweeps it, the GPU uses gSaP's subdivision on all three axes, with cells
//! as wide as the widest "regular" box, and no sweep:
//! 1. `stats`: the valid boxes' low-corner extent, and a histogram of the boxes' widths (the
//!    largest side) by binary exponent, with each bin's largest width;
//! 2. on the host: the cell size is the largest width among all but at most
//!    [`MAX_OVERSIZE`] `+ n / 16384` of the widest boxes (those are "oversize", found by the
//!    exponent histogram), and the grid is the CPU's (`world::grid`, at most four cells per box);
//! 3. `assign`, a prefix sum and `scatter`: a counting sort of the regular boxes by the cell of
//!    their low corner (boxes of one cell next to each other in memory);
//! 4. `near_pairs`: two regular boxes that overlap have low corners less than a cell apart on
//!    every axis (each box is at most a cell wide), so each box tests the boxes of the 27 cells
//!    around its own, and every oversize box; `far_pairs`: a block per oversize box tests every
//!    box after it;
//! 5. box `i`'s list holds the `j > i` that overlap it: counted, then a prefix sum gives each
//!    list's place, then written (regular lists sorted in place, oversize lists written in
//!    order), so the pairs come back in the CPU's order.
//!
//! The cell size is the largest regular width times `1 + 1e-6` plus a few units in the last
//! place of the largest coordinate: two low corners at most a width apart then fall in cells at
//! most one apart even after rounding. The overlap test is the CPU's (closed boxes), in `f64`.
//! Boxes with a NaN, an infinite coordinate or `min > max` overlap nothing, as on the CPU.
//!
//! Limits: fewer than 2^31 boxes (an error beyond), and list places are 32-bit, so the answer
//! is right only below 2^32 pairs (a partners buffer of 16 GiB; the CPU path has no such
//! limit). Boxes the grid would take badly go to the CPU's sweep instead, decided on the host
//! from the statistics: more than `64 + n / 16384` boxes over four times the median width (they
//! would set the cell size), or low corners spread over more than four cells per box (a far
//! outlier: the cells would grow and hold clusters whole). [`GpuBroadPhase::pairs`] answers
//! `None` for those and [`GpuBroadPhase::sweep_and_prune`] runs the CPU's sweep; this decision
//! was added after the device runs, so it has not run on a GPU (its host logic is tested).
#![allow(unsafe_code)]
// SAFETY (the module's one concern): kernel launches are `unsafe` in cudarc because the
// arguments cannot be checked against the kernel's signature. Each launch below passes the
// arguments in the order and types of `kernels.cu`, every buffer is allocated by this module
// with the length the kernel indexes (`n` boxes of 6 doubles, `cells + 1` counters, the pair
// total), and every index a kernel computes is bounded by a length passed beside it.

use super::grid::{flat, CellGrid};
use super::swept::Aabb;
use cudarc::driver::{
    CudaContext, CudaFunction, CudaSlice, CudaStream, LaunchConfig, PushKernelArg,
};
use rayon::prelude::*;
use std::sync::Arc;

/// The widest boxes kept out of the cells, at most this many plus one in 16,384 boxes: each is
/// tested against every box (one block of threads each).
pub const MAX_OVERSIZE: usize = 64;

const SOURCE: &str = include_str!("kernels.cu");
const BLOCK: u32 = 256;
const SCAN_TILE: u32 = 4096;
const SCAN_THREADS: u32 = 1024;
const EXP_BINS: usize = 2048;
const KERNELS: [&str; 7] = [
    "stats",
    "assign",
    "scatter",
    "near_pairs",
    "far_pairs",
    "scan_tiles",
    "scan_add",
];

/// What went wrong on the GPU path: no driver or device, the kernels' compilation, or a CUDA
/// call. The CPU path ([`super::broad::sweep_and_prune`]) answers the same question.
#[derive(Debug, thiserror::Error)]
#[error("GPU broad phase: {0}")]
pub struct GpuError(String);

impl From<cudarc::driver::DriverError> for GpuError {
    fn from(e: cudarc::driver::DriverError) -> Self {
        Self(format!("CUDA driver: {e:?}"))
    }
}

/// Boxes copied to the GPU ([`GpuBroadPhase::upload`]), to be queried there.
pub struct GpuBoxes {
    data: CudaSlice<f64>,
    n: u32,
}

impl GpuBoxes {
    /// How many boxes.
    pub fn len(&self) -> usize {
        self.n as usize
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }
}

/// The pairs found on the GPU, still there: box `i`'s partners `j > i` are
/// `partners[offsets[i]..offsets[i + 1]]`, sorted.
pub struct GpuPairs {
    offsets: Option<CudaSlice<u32>>,
    partners: Option<CudaSlice<u32>>,
    n: u32,
    total: usize,
    stream: Arc<CudaStream>,
}

impl GpuPairs {
    /// How many pairs.
    pub fn len(&self) -> usize {
        self.total
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.total == 0
    }

    /// The pairs `(i, j)`, `i < j`, sorted: [`super::broad::sweep_and_prune`]'s answer.
    pub fn to_vec(&self) -> Result<Vec<(u32, u32)>, GpuError> {
        let (Some(offsets), Some(partners)) = (&self.offsets, &self.partners) else {
            return Ok(Vec::new());
        };
        let offsets = self.stream.clone_dtoh(offsets)?;
        let partners = self.stream.clone_dtoh(partners)?;
        self.stream.synchronize()?;
        let mut pairs = vec![(0u32, 0u32); self.total];
        // Each box's list into its place, boxes in parallel chunks.
        let n = self.n as usize;
        let chunk = n.div_ceil(rayon::current_num_threads() * 4).max(1024);
        let starts: Vec<usize> = (0..n).step_by(chunk).collect();
        let mut rest = pairs.as_mut_slice();
        let mut pieces = Vec::with_capacity(starts.len());
        for &s in &starts {
            let e = (s + chunk).min(n);
            let (piece, tail) = rest.split_at_mut((offsets[e] - offsets[s]) as usize);
            pieces.push((s, e, piece));
            rest = tail;
        }
        pieces.into_par_iter().for_each(|(s, e, piece)| {
            let base = offsets[s] as usize;
            for i in s..e {
                for k in offsets[i] as usize..offsets[i + 1] as usize {
                    piece[k - base] = (i as u32, partners[k]);
                }
            }
        });
        Ok(pairs)
    }
}

/// The GPU broad phase: a CUDA context, a stream and the compiled kernels. Build once, query
/// many times; not shared between threads at once (each call uses the one stream).
pub struct GpuBroadPhase {
    ctx: Arc<CudaContext>,
    stream: Arc<CudaStream>,
    kernels: Vec<CudaFunction>,
}

/// What the host decides from the `stats` kernel's answer.
enum Planned {
    /// Fewer than two valid boxes.
    Empty,
    /// The grid and the oversize split.
    Grid(Plan),
    /// Cells that would be too coarse for the GPU's plan: more boxes much wider than the median
    /// than it keeps out (they would set the cell size), or an extent that needs more cells
    /// than the grid may have (a far outlier; boxes that are points). The CPU's sweep sorts
    /// inside its cells and takes these in its stride.
    Cpu,
}

/// The grid and the oversize split the host chooses from the `stats` kernel's answer.
struct Plan {
    origin: [f64; 3],
    size: f64,
    n: [u32; 3],
    wmax: f64,
    oversize: u32,
}

impl GpuBroadPhase {
    /// Loads the CUDA driver and NVRTC, opens device 0 and compiles the kernels; an error (not a
    /// panic) where CUDA, NVRTC or a device is missing.
    pub fn new() -> Result<Self, GpuError> {
        // SAFETY: these only try to load the libraries (no CUDA call is made).
        let driver = unsafe { cudarc::driver::sys::is_culib_present() };
        if !driver {
            return Err(GpuError("no CUDA driver library (libcuda) found".into()));
        }
        let nvrtc = unsafe { cudarc::nvrtc::sys::is_culib_present() };
        if !nvrtc {
            return Err(GpuError(
                "no NVRTC library (libnvrtc) found: install the CUDA toolkit or put its lib64 \
                 folder on LD_LIBRARY_PATH"
                    .into(),
            ));
        }
        let count = CudaContext::device_count()?;
        if count < 1 {
            return Err(GpuError("no CUDA device".into()));
        }
        let ctx = CudaContext::new(0)?;
        let stream = ctx.default_stream();
        let ptx = cudarc::nvrtc::compile_ptx(SOURCE)
            .map_err(|e| GpuError(format!("compiling the kernels: {e:?}")))?;
        let module = ctx.load_module(ptx)?;
        let kernels = KERNELS
            .iter()
            .map(|name| module.load_function(name))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            ctx,
            stream,
            kernels,
        })
    }

    /// The device's name, as the driver gives it.
    pub fn device_name(&self) -> Result<String, GpuError> {
        Ok(self.ctx.name()?)
    }

    /// [`super::broad::sweep_and_prune`] on the GPU: the boxes copied there, the pairs found and
    /// copied back, sorted. The same pairs in the same order as the CPU's.
    pub fn sweep_and_prune(&self, boxes: &[Aabb]) -> Result<Vec<(u32, u32)>, GpuError> {
        let on_gpu = self.upload(boxes)?;
        match self.pairs(&on_gpu)? {
            Some(pairs) => pairs.to_vec(),
            // Boxes the GPU's cells would take badly: the CPU's sweep (see `pairs`).
            None => Ok(super::broad::sweep_and_prune(
                boxes,
                super::broad::SweepAxis::LargestVariance,
            )),
        }
    }

    /// Copies boxes to the GPU.
    pub fn upload(&self, boxes: &[Aabb]) -> Result<GpuBoxes, GpuError> {
        let n = u32::try_from(boxes.len())
            .ok()
            .filter(|&n| n < u32::MAX / 2)
            .ok_or_else(|| GpuError("more than 2^31 boxes".into()))?;
        let mut numbers = vec![0.0f64; 6 * boxes.len()];
        numbers
            .par_chunks_mut(6 * 4096)
            .zip(boxes.par_chunks(4096))
            .for_each(|(out, bs)| {
                for (o, b) in out.chunks_exact_mut(6).zip(bs) {
                    o.copy_from_slice(&flat(b));
                }
            });
        let data = if numbers.is_empty() {
            self.stream.alloc_zeros::<f64>(6)?
        } else {
            self.stream.clone_htod(&numbers)?
        };
        Ok(GpuBoxes { data, n })
    }

    /// Every overlapping pair of the uploaded boxes, found on the GPU and left there (the call
    /// returns once they are found); `None` for boxes the GPU's grid would take badly (more
    /// than `64 + n / 16384` boxes over four times the median width, or an extent needing more
    /// cells than four per box, as a far outlier does): the CPU's sweep answers those
    /// ([`Self::sweep_and_prune`] falls back to it).
    pub fn pairs(&self, boxes: &GpuBoxes) -> Result<Option<GpuPairs>, GpuError> {
        let n = boxes.n;
        let empty = GpuPairs {
            offsets: None,
            partners: None,
            n,
            total: 0,
            stream: self.stream.clone(),
        };
        if n < 2 {
            return Ok(Some(empty));
        }
        let s = &self.stream;
        let k = &self.kernels;
        // 1. statistics
        let mut bounds = s.clone_htod(&[u64::MAX, u64::MAX, u64::MAX, 0, 0, 0])?;
        let mut hist = s.alloc_zeros::<u32>(EXP_BINS)?;
        let mut bin_max = s.alloc_zeros::<u64>(EXP_BINS)?;
        let blocks = n.div_ceil(BLOCK).min(528);
        let mut b = s.launch_builder(&k[0]);
        b.arg(&boxes.data)
            .arg(&n)
            .arg(&mut bounds)
            .arg(&mut hist)
            .arg(&mut bin_max);
        // SAFETY: module docs.
        unsafe { b.launch(config(blocks, BLOCK)) }?;
        let bounds = s.clone_dtoh(&bounds)?;
        let hist = s.clone_dtoh(&hist)?;
        let bin_max = s.clone_dtoh(&bin_max)?;
        s.synchronize()?;
        let plan = match plan(n, &bounds, &hist, &bin_max) {
            Planned::Empty => return Ok(Some(empty)),
            Planned::Cpu => return Ok(None),
            Planned::Grid(plan) => plan,
        };
        // 2. the counting sort into cells
        let cells = plan.n[0] as usize * plan.n[1] as usize * plan.n[2] as usize;
        let cells_u32 = cells as u32;
        let mut cell_of = s.alloc_zeros::<u32>(n as usize)?;
        let mut cell_start = s.alloc_zeros::<u32>(cells + 1)?;
        let mut over_list = s.alloc_zeros::<u32>(plan.oversize.max(1) as usize)?;
        let mut over_n = s.alloc_zeros::<u32>(1)?;
        let grid = n.div_ceil(BLOCK);
        let [ox, oy, oz] = plan.origin;
        let [nx, ny, nz] = plan.n;
        let mut b = s.launch_builder(&k[1]);
        b.arg(&boxes.data)
            .arg(&n)
            .arg(&ox)
            .arg(&oy)
            .arg(&oz)
            .arg(&plan.size);
        b.arg(&nx).arg(&ny).arg(&nz).arg(&plan.wmax);
        b.arg(&mut cell_of)
            .arg(&mut cell_start)
            .arg(&mut over_list)
            .arg(&mut over_n);
        // SAFETY: module docs.
        unsafe { b.launch(config(grid, BLOCK)) }?;
        self.scan(&mut cell_start, cells_u32 + 1)?;
        let mut cell_fill = s.alloc_zeros::<u32>(cells)?;
        let mut sorted_id = s.alloc_zeros::<u32>(n as usize)?;
        let mut sorted_boxes = s.alloc_zeros::<f64>(6 * n as usize)?;
        let mut b = s.launch_builder(&k[2]);
        b.arg(&boxes.data)
            .arg(&n)
            .arg(&cell_of)
            .arg(&cell_start)
            .arg(&mut cell_fill);
        b.arg(&mut sorted_id).arg(&mut sorted_boxes);
        // SAFETY: module docs.
        unsafe { b.launch(config(grid, BLOCK)) }?;
        drop(cell_fill);
        drop(cell_of);
        // 3. count, place, write
        let mut count = s.alloc_zeros::<u32>(n as usize + 1)?;
        let mut partners = s.alloc_zeros::<u32>(1)?;
        for write in [0i32, 1] {
            let mut b = s.launch_builder(&k[3]);
            b.arg(&sorted_boxes)
                .arg(&sorted_id)
                .arg(&cell_start)
                .arg(&cells_u32);
            b.arg(&ox)
                .arg(&oy)
                .arg(&oz)
                .arg(&plan.size)
                .arg(&nx)
                .arg(&ny)
                .arg(&nz);
            b.arg(&boxes.data).arg(&over_list).arg(&plan.oversize);
            if write == 0 {
                // `count` is the counts now, and becomes the offsets after the scan.
                let offsets_unused = s.alloc_zeros::<u32>(1)?;
                b.arg(&mut count)
                    .arg(&offsets_unused)
                    .arg(&mut partners)
                    .arg(&write);
                // SAFETY: module docs (`offset` and `partners` are not read when counting).
                unsafe { b.launch(config(grid, BLOCK)) }?;
                if plan.oversize > 0 {
                    let mut b = s.launch_builder(&k[4]);
                    b.arg(&boxes.data).arg(&n).arg(&over_list).arg(&mut count);
                    b.arg(&offsets_unused).arg(&mut partners).arg(&write);
                    // SAFETY: module docs.
                    unsafe { b.launch(config(plan.oversize, BLOCK)) }?;
                }
                self.scan(&mut count, n + 1)?;
                let total = s.clone_dtoh(&count.slice(n as usize..))?;
                s.synchronize()?;
                let total = total.first().copied().unwrap_or(0) as usize;
                if total == 0 {
                    return Ok(Some(empty));
                }
                partners = s.alloc_zeros::<u32>(total)?;
            } else {
                let mut unused = s.alloc_zeros::<u32>(1)?;
                b.arg(&mut unused)
                    .arg(&count)
                    .arg(&mut partners)
                    .arg(&write);
                // SAFETY: module docs.
                unsafe { b.launch(config(grid, BLOCK)) }?;
                if plan.oversize > 0 {
                    let mut b = s.launch_builder(&k[4]);
                    b.arg(&boxes.data).arg(&n).arg(&over_list).arg(&mut unused);
                    b.arg(&count).arg(&mut partners).arg(&write);
                    // SAFETY: module docs.
                    unsafe { b.launch(config(plan.oversize, BLOCK)) }?;
                }
            }
        }
        s.synchronize()?;
        let total = partners.len();
        Ok(Some(GpuPairs {
            offsets: Some(count),
            partners: Some(partners),
            n,
            total,
            stream: self.stream.clone(),
        }))
    }

    /// Exclusive prefix sum of the first `n` values, in place.
    fn scan(&self, values: &mut CudaSlice<u32>, n: u32) -> Result<(), GpuError> {
        let tiles = n.div_ceil(SCAN_TILE);
        let mut sums = self.stream.alloc_zeros::<u32>(tiles.max(1) as usize)?;
        let mut b = self.stream.launch_builder(&self.kernels[5]);
        b.arg(&mut *values).arg(&n).arg(&mut sums);
        // SAFETY: module docs.
        unsafe { b.launch(config(tiles, SCAN_THREADS)) }?;
        if tiles > 1 {
            self.scan(&mut sums, tiles)?;
            let mut b = self.stream.launch_builder(&self.kernels[6]);
            b.arg(&mut *values).arg(&n).arg(&sums);
            // SAFETY: module docs.
            unsafe { b.launch(config(tiles, SCAN_THREADS)) }?;
        }
        Ok(())
    }
}

fn config(blocks: u32, threads: u32) -> LaunchConfig {
    LaunchConfig {
        grid_dim: (blocks.max(1), 1, 1),
        block_dim: (threads, 1, 1),
        shared_mem_bytes: 0,
    }
}

/// The ordered bits of `kernels.cu` back to the double.
fn unordered(u: u64) -> f64 {
    let top = 1u64 << 63;
    f64::from_bits(if u & top != 0 { u ^ top } else { !u })
}

/// The grid and the oversize split (module docs, step 2); `None` when fewer than two boxes are
/// valid.
fn plan(n: u32, bounds: &[u64], hist: &[u32], bin_max: &[u64]) -> Planned {
    let valid: u64 = hist.iter().map(|&c| u64::from(c)).sum();
    if valid < 2 {
        return Planned::Empty;
    }
    let allowed = MAX_OVERSIZE as u64 + u64::from(n) / 16384;
    // The smallest exponent bin with at most `allowed` boxes in the bins above it.
    let mut above = 0u64;
    let mut cut = EXP_BINS - 1;
    for e in (0..EXP_BINS).rev() {
        if hist[e] == 0 {
            continue;
        }
        if above > allowed {
            break;
        }
        cut = e;
        above += u64::from(hist[e]);
    }
    let oversize: u64 = hist[cut + 1..].iter().map(|&c| u64::from(c)).sum();
    let wmax = f64::from_bits(bin_max[cut]);
    let lo = [
        unordered(bounds[0]),
        unordered(bounds[1]),
        unordered(bounds[2]),
    ];
    let hi = [
        unordered(bounds[3]),
        unordered(bounds[4]),
        unordered(bounds[5]),
    ];
    let grid = CellGrid::new(valid, lo, hi, wmax);
    // The median width, from above: the largest width of the bin holding it.
    let mut below = 0u64;
    let median_bin = (0..EXP_BINS)
        .find(|&e| {
            below += u64::from(hist[e]);
            2 * below > valid
        })
        .unwrap_or(EXP_BINS - 1);
    let median_above = f64::from_bits(bin_max[median_bin]);
    if grid.coarse || wmax > 4.0 * median_above {
        return Planned::Cpu;
    }
    Planned::Grid(Plan {
        origin: grid.origin,
        size: grid.size,
        n: grid.n,
        wmax,
        oversize: oversize as u32,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kernels_compile_where_nvrtc_is_present() {
        // NVRTC compiles without a GPU: where the library is found (the CUDA toolkit, or pip's
        // nvidia-cuda-nvrtc on LD_LIBRARY_PATH), the kernels must compile with every entry point.
        // SAFETY: only loads the library.
        if !unsafe { cudarc::nvrtc::sys::is_culib_present() } {
            eprintln!("skipped: no NVRTC library here (the CUDA toolkit is absent)");
            return;
        }
        let ptx = cudarc::nvrtc::compile_ptx(SOURCE);
        assert!(ptx.is_ok(), "{:?}", ptx.err());
        let text = ptx.map(|p| p.to_src()).unwrap_or_default();
        for name in KERNELS {
            assert!(text.contains(&format!(".entry {name}(")), "{name} missing");
        }
    }

    /// `kernels.cu`'s `ordered`: a double's bits as an unsigned integer of the same order.
    fn ordered(v: f64) -> u64 {
        let bits = v.to_bits() as i64;
        if bits >= 0 {
            (bits as u64) | (1 << 63)
        } else {
            !(bits as u64)
        }
    }

    #[test]
    fn ordered_bits_round_trip() {
        let values = [-1e300, -3.5f64, -0.0, 0.0, 1e-300, 2.0, 1e300];
        for b in values {
            assert_eq!(unordered(ordered(b)).to_bits(), b.to_bits());
        }
        // The order is the values' (the kernels take minima and maxima of the bits).
        for w in values.windows(2) {
            assert!(ordered(w[0]) < ordered(w[1]), "{w:?}");
        }
    }

    #[test]
    fn plan_keeps_the_widest_out_and_bounds_the_cells() {
        // 1,000 boxes of width 0.01 and 3 of width 10 (binary exponents 1016 and 1026).
        let mut hist = vec![0u32; EXP_BINS];
        let mut bin_max = vec![0u64; EXP_BINS];
        let e_small = ((0.01f64.to_bits() >> 52) & 0x7ff) as usize;
        let e_big = ((10.0f64.to_bits() >> 52) & 0x7ff) as usize;
        hist[e_small] = 1000;
        bin_max[e_small] = 0.01f64.to_bits();
        hist[e_big] = 3;
        bin_max[e_big] = 10.0f64.to_bits();
        // Low corners over a cube of side 0.1: 11^3 cells of 0.01, under four per box.
        let bounds = [
            ordered(0.0),
            ordered(0.0),
            ordered(0.0),
            ordered(0.1),
            ordered(0.1),
            ordered(0.1),
        ];
        let Planned::Grid(p) = plan(1003, &bounds, &hist, &bin_max) else {
            unreachable!("a grid for 1,000 small boxes and 3 walls")
        };
        assert_eq!(p.oversize, 3);
        assert_eq!(p.wmax, 0.01);
        assert!(p.size >= 0.01 * (1.0 + 1e-6));
        let cells = p.n.iter().map(|&c| f64::from(c)).product::<f64>();
        assert!(cells <= 4.0 * 1003.0 + 64.0, "{cells} cells");
        // More walls than it keeps out (100 > 64) would set the cells: the CPU's sweep is asked.
        hist[e_big] = 100;
        assert!(matches!(plan(1100, &bounds, &hist, &bin_max), Planned::Cpu));
        // Nor where the extent needs too many cells (one box far away).
        hist[e_big] = 3;
        let far = [
            ordered(0.0),
            ordered(0.0),
            ordered(0.0),
            ordered(1e6),
            ordered(0.1),
            ordered(0.1),
        ];
        assert!(matches!(plan(1003, &far, &hist, &bin_max), Planned::Cpu));
        // Fewer than two valid boxes: nothing to pair.
        let mut one = vec![0u32; EXP_BINS];
        one[e_small] = 1;
        assert!(matches!(plan(1, &bounds, &one, &bin_max), Planned::Empty));
    }

    /// The `stats` kernel's answer computed on the CPU (the same rules: valid boxes only, the
    /// low corners' extent as ordered bits, widths by binary exponent).
    fn stats_on_cpu(boxes: &[Aabb]) -> ([u64; 6], Vec<u32>, Vec<u64>) {
        let mut bounds = [u64::MAX, u64::MAX, u64::MAX, 0, 0, 0];
        let mut hist = vec![0u32; EXP_BINS];
        let mut bin_max = vec![0u64; EXP_BINS];
        for b in boxes {
            if !(b.min.is_finite() && b.max.is_finite() && b.min.cmple(b.max).all()) {
                continue;
            }
            for k in 0..3 {
                bounds[k] = bounds[k].min(ordered(b.min[k]));
                bounds[3 + k] = bounds[3 + k].max(ordered(b.min[k]));
            }
            let w = (b.max - b.min).max_element();
            let e = ((w.to_bits() >> 52) & 0x7ff) as usize;
            hist[e] += 1;
            bin_max[e] = bin_max[e].max(w.to_bits());
        }
        (bounds, hist, bin_max)
    }

    #[test]
    fn the_measured_sets_take_the_gpu_grid_and_outliers_the_cpu() {
        use crate::math::Vec3;
        // The benchmark's boxes (about two pairs each) and the device test's 200,000 with 40
        // walls, from a small generator: the plan the device runs took must still be a grid.
        let mut state = 12345u64;
        let mut unit = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in [10_000usize, 100_000] {
            let s = (1.0 / (16.0 * n as f64)).cbrt();
            let boxes: Vec<Aabb> = (0..n)
                .map(|_| {
                    let c = Vec3::new(unit(), unit(), unit());
                    Aabb {
                        min: c - Vec3::splat(s),
                        max: c + Vec3::splat(s),
                    }
                })
                .collect();
            let (bounds, hist, bin_max) = stats_on_cpu(&boxes);
            assert!(matches!(
                plan(n as u32, &bounds, &hist, &bin_max),
                Planned::Grid(_)
            ));
            let mut walled = boxes.clone();
            for k in 0..40 {
                let c = Vec3::new(unit(), unit(), unit());
                walled[k * (n / 41)] = Aabb {
                    min: c - Vec3::new(0.2, 0.01, 0.3),
                    max: c + Vec3::new(0.2, 0.01, 0.3),
                };
            }
            let (bounds, hist, bin_max) = stats_on_cpu(&walled);
            let Planned::Grid(p) = plan(n as u32, &bounds, &hist, &bin_max) else {
                unreachable!("walls within the allowance keep the grid")
            };
            assert_eq!(p.oversize, 40);
            // One box far away: the CPU's sweep.
            let mut far = boxes;
            far[7] = Aabb {
                min: Vec3::splat(1e6),
                max: Vec3::splat(1e6 + 0.01),
            };
            let (bounds, hist, bin_max) = stats_on_cpu(&far);
            assert!(matches!(
                plan(n as u32, &bounds, &hist, &bin_max),
                Planned::Cpu
            ));
        }
    }
}
