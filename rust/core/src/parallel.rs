//! Thread pools for the batch kernels.
//!
//! Every batch kernel runs on `pool(resolve_threads(n_threads)?)`: `Some(k)` asks
//! for `k` threads; `None` takes `CYCLOMECH_THREADS` from the environment, or the
//! number of cores. Pools are built once per thread count and cached, because building one
//! costs far more than a small kernel call. Inside Dask workers the Python layer
//! sets one thread so that processes and threads do not oversubscribe the cores.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use rayon::{ThreadPool, ThreadPoolBuilder};

/// Name of the environment variable that sets the default thread count.
pub const THREADS_ENV: &str = "CYCLOMECH_THREADS";

/// Largest thread count accepted (a typo such as 10000 should not spawn 10000 threads).
pub const MAX_THREADS: usize = 1024;

/// Errors of the thread-count settings.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ThreadsError {
    #[error("n_threads must be an integer between 1 and {max}; got {value}")]
    BadCount { value: i64, max: usize },
    #[error("environment variable {var} must be an integer between 1 and {max}; got {value:?}")]
    BadEnv {
        var: &'static str,
        value: String,
        max: usize,
    },
    #[error("could not start a pool of {threads} threads: {reason}")]
    Build { threads: usize, reason: String },
}

/// Resolve the thread count: the explicit argument, else `CYCLOMECH_THREADS`, else
/// the number of available cores.
pub fn resolve_threads(n_threads: Option<i64>) -> Result<usize, ThreadsError> {
    if let Some(k) = n_threads {
        if k < 1 || k as u64 > MAX_THREADS as u64 {
            return Err(ThreadsError::BadCount {
                value: k,
                max: MAX_THREADS,
            });
        }
        return Ok(k as usize);
    }
    if let Ok(raw) = std::env::var(THREADS_ENV) {
        let trimmed = raw.trim();
        if !trimmed.is_empty() {
            return match trimmed.parse::<usize>() {
                Ok(k) if (1..=MAX_THREADS).contains(&k) => Ok(k),
                _ => Err(ThreadsError::BadEnv {
                    var: THREADS_ENV,
                    value: raw,
                    max: MAX_THREADS,
                }),
            };
        }
    }
    Ok(cores())
}

/// Number of cores available to this process, read once: the standard library
/// re-reads the cgroup files on every call, which costs tens of microseconds.
pub fn cores() -> usize {
    static CORES: OnceLock<usize> = OnceLock::new();
    *CORES.get_or_init(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    })
}

/// The cached pools, with the process that built them.
struct Pools {
    /// `std::process::id()` when these pools were built.
    pid: u32,
    by_threads: HashMap<usize, Arc<ThreadPool>>,
}

fn pools() -> &'static Mutex<Pools> {
    static POOLS: OnceLock<Mutex<Pools>> = OnceLock::new();
    POOLS.get_or_init(|| {
        Mutex::new(Pools {
            pid: std::process::id(),
            by_threads: HashMap::new(),
        })
    })
}

/// The cached pool with `threads` threads.
///
/// **After `fork`.** A child made by `fork` (Python's `multiprocessing` default
/// on Linux, joblib, some Dask set-ups) inherits the parent's pools but not their
/// threads: work sent to them would wait forever. So the cache remembers the
/// process id that built it, and a call from another process id drops the
/// inherited pools and builds fresh ones in the child. The inherited pools are
/// leaked, not dropped: their drop would signal worker threads that do not exist
/// in the child, and their memory is the parent's copy anyway.
pub fn pool(threads: usize) -> Result<Arc<ThreadPool>, ThreadsError> {
    // A poisoned lock only means another thread panicked while holding it; the map
    // itself is still valid, so recover it instead of propagating the panic.
    let mut cache = pools().lock().unwrap_or_else(|e| e.into_inner());
    let pid = std::process::id();
    if cache.pid != pid {
        for (_, inherited) in cache.by_threads.drain() {
            std::mem::forget(inherited);
        }
        cache.pid = pid;
    }
    if let Some(p) = cache.by_threads.get(&threads) {
        return Ok(Arc::clone(p));
    }
    let built = ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("cyclomech-{i}"))
        .build()
        .map_err(|e| ThreadsError::Build {
            threads,
            reason: e.to_string(),
        })?;
    let built = Arc::new(built);
    cache.by_threads.insert(threads, Arc::clone(&built));
    Ok(built)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn explicit_count_is_validated() {
        assert_eq!(resolve_threads(Some(3)), Ok(3));
        assert!(matches!(
            resolve_threads(Some(0)),
            Err(ThreadsError::BadCount { value: 0, .. })
        ));
        assert!(resolve_threads(Some(-2)).is_err());
        assert!(resolve_threads(Some(1_000_000)).is_err());
    }

    #[test]
    fn pool_runs_with_requested_threads() {
        let n = pool(resolve_threads(Some(2)).unwrap())
            .unwrap()
            .install(rayon::current_num_threads);
        assert_eq!(n, 2);
    }
}
