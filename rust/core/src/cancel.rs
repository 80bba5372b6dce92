//! Cutting a long kernel call short when the user presses Ctrl-C.
//!
//! Pure bookkeeping, no signals here: the Python bindings route SIGINT to
//! [`flag`] (chained after the interpreter's own handler) and bracket every kernel
//! call made from the interpreter's main thread with [`arm`] / [`Armed::finish`].
//! The kernels poll [`requested`] at the start of every chunk of their parallel
//! loops (a relaxed load, free at that grain) and stop early when it is set.
//!
//! The rule, decided: **a call that was cut short never returns its output.** A
//! kernel that stops early leaves its output partly written, so the caller must
//! throw the whole result away: [`Armed::finish`] says so for the armed call, and
//! [`Watch::cut_short`] for any other call that may have run while an armed one
//! was being cut (a kernel started from another thread sees the same flag, since
//! the rayon tasks of concurrent calls cannot tell whose they are). Nothing polls
//! outside an armed call: a SIGINT between calls, or while only other threads
//! run kernels, changes nothing.
//!
//! Ordering (all `SeqCst`): `arm` clears the signal, then arms; `finish` disarms,
//! then counts a cut, then clears the signal. A kernel that saw
//! [`requested`] did so while armed, so before that disarm: a [`Watch`] taken
//! before the kernel then sees either the flags still set or the count moved.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::SeqCst};
use std::sync::{Arc, OnceLock};

/// Set while a kernel called from the interpreter's main thread runs.
static ARMED: AtomicBool = AtomicBool::new(false);
/// How many armed calls were cut short so far.
static CUTS: AtomicU64 = AtomicU64::new(0);

/// The flag a SIGINT handler sets (`signal_hook::flag::register` takes an `Arc`).
pub fn flag() -> &'static Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    FLAG.get_or_init(|| Arc::new(AtomicBool::new(false)))
}

/// Should the running kernel stop? True only while an armed call runs and a
/// SIGINT came after it was armed. Kernels call this at the start of each chunk.
#[inline]
pub fn requested() -> bool {
    ARMED.load(SeqCst) && flag().load(SeqCst)
}

/// An armed call: made from the main thread, its kernel may be cut short.
#[must_use = "finish() says whether the output may be used"]
pub struct Armed(());

/// Arm the kernel call about to run (one at a time: the main thread's). A signal
/// that came before this call is not this call's.
pub fn arm() -> Armed {
    flag().store(false, SeqCst);
    ARMED.store(true, SeqCst);
    Armed(())
}

impl Armed {
    /// Disarm; true if a SIGINT came while armed, so the output must be dropped.
    pub fn finish(self) -> bool {
        ARMED.store(false, SeqCst);
        let cut = flag().load(SeqCst);
        if cut {
            CUTS.fetch_add(1, SeqCst);
        }
        flag().store(false, SeqCst);
        cut
    }
}

/// A kernel call from any other thread: it cannot be interrupted itself, but its
/// tasks may have seen an armed call's signal and stopped early.
pub struct Watch(u64);

/// Start watching the kernel call about to run.
pub fn watch() -> Watch {
    Watch(CUTS.load(SeqCst))
}

impl Watch {
    /// True if the watched call may have stopped early (module doc), so its
    /// output must be dropped.
    pub fn cut_short(&self) -> bool {
        requested() || CUTS.load(SeqCst) != self.0
    }
}
