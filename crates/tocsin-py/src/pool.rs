//! The thread pool behind every parallel call (mesh builds, batches), safe after `fork`.
//!
//! rayon's global pool lives in the process that made it: a child made by `os.fork()` (the
//! default start method of `multiprocessing` on Linux, `ProcessPoolExecutor`, PyTorch's
//! `DataLoader` workers) inherits its bookkeeping but none of its threads, and its first
//! parallel call waited forever. So the binding never uses the global pool: it keeps its own,
//! tagged with the process id that made it. A call from another process (a forked child)
//! builds a fresh pool for that process; the inherited one is leaked, never dropped, since
//! dropping it would signal threads that do not exist there. The lock is only taken with the
//! GIL held, and `fork` from Python holds the GIL, so no child inherits it locked.

use crate::errors::error;
use pyo3::prelude::*;
use rayon::{ThreadPool, ThreadPoolBuilder};
use std::sync::{Arc, Mutex};

type Tagged = Option<(u32, Arc<ThreadPool>)>;

static POOL: Mutex<Tagged> = Mutex::new(None);

/// This process's pool (built on first use; `RAYON_NUM_THREADS` sets its size).
fn pool(py: Python<'_>) -> PyResult<Arc<ThreadPool>> {
    let pid = std::process::id();
    let mut slot = POOL.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some((owner, pool)) = slot.as_ref() {
        if *owner == pid {
            return Ok(pool.clone());
        }
    }
    let fresh = Arc::new(
        ThreadPoolBuilder::new()
            .thread_name(|i| format!("tocsin-{i}"))
            .build()
            .map_err(|e| error(py, "TocsinError", format!("cannot start threads: {e}")))?,
    );
    if let Some(inherited) = slot.replace((pid, fresh.clone())) {
        std::mem::forget(inherited);
    }
    Ok(fresh)
}

/// Runs `work` in this process's pool with the GIL released.
pub(crate) fn run<T: Send>(py: Python<'_>, work: impl FnOnce() -> T + Send) -> PyResult<T> {
    let pool = pool(py)?;
    Ok(py.detach(|| pool.install(work)))
}
