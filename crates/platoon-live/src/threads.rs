//! Where the updater's threads run and how they yield to the others (Linux; elsewhere these
//! calls do nothing and say so).
//!
//! Two findings of `platoon bench dynamic` on a 2-core machine, one tracer thread beside one
//! updater thread:
//! - The game thread's `submit` wakes the updater on the game thread's own core and, with the
//!   normal policy, is pushed off that core until the scheduler's next balancing tick: 3-5 ms
//!   at the 99th percentile. The updater's threads therefore run as batch work
//!   (`SCHED_BATCH`): they get the time left over, and their wake-ups preempt nobody.
//! - The scheduler places the woken updater and the tracer's thread on the same core often
//!   enough to slow the render by a fifth. Pinning them to different cores (the tracer's
//!   threads inherit the mask of the thread that creates the device) removes it; a game that
//!   manages its own threads passes the cores to use (`UpdaterThreads::cpus`).

/// Marks the calling thread as batch work; false where the system has no such class or refused.
#[cfg(target_os = "linux")]
pub(crate) fn run_as_batch() -> bool {
    let param = libc::sched_param { sched_priority: 0 };
    // SAFETY: a syscall on the calling thread (pid 0) with a valid parameter; it only reads
    // `param`.
    unsafe { libc::sched_setscheduler(0, libc::SCHED_BATCH, &param) == 0 }
}

#[cfg(not(target_os = "linux"))]
pub(crate) fn run_as_batch() -> bool {
    false
}

/// The cores the calling thread may run on, ascending (None where this cannot be asked).
#[cfg(target_os = "linux")]
pub fn current_cpus() -> Option<Vec<usize>> {
    // SAFETY: cpu_set_t is plain bits (zeroed is the empty set); the syscall writes at most
    // its size into it.
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        if libc::sched_getaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &mut set) != 0 {
            return None;
        }
        Some(
            (0..libc::CPU_SETSIZE as usize)
                .filter(|&c| libc::CPU_ISSET(c, &set))
                .collect(),
        )
    }
}

#[cfg(not(target_os = "linux"))]
pub fn current_cpus() -> Option<Vec<usize>> {
    None
}

/// Restricts the calling thread (and the threads it starts from now on) to `cpus`; false when
/// the list is empty, names no usable core, or the system refused.
#[cfg(target_os = "linux")]
pub fn pin_current_thread(cpus: &[usize]) -> bool {
    let usable: Vec<usize> = cpus
        .iter()
        .copied()
        .filter(|&c| c < libc::CPU_SETSIZE as usize)
        .collect();
    if usable.is_empty() {
        return false;
    }
    // SAFETY: as in `current_cpus`; CPU_SET is given indices below CPU_SETSIZE.
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        for c in usable {
            libc::CPU_SET(c, &mut set);
        }
        libc::sched_setaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &set) == 0
    }
}

#[cfg(not(target_os = "linux"))]
pub fn pin_current_thread(_cpus: &[usize]) -> bool {
    false
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;

    #[test]
    fn a_thread_pins_to_one_core_and_back_and_runs_as_batch() {
        std::thread::spawn(|| {
            let before = current_cpus().expect("Linux answers sched_getaffinity");
            assert!(!before.is_empty());
            assert!(pin_current_thread(&before[..1]));
            assert_eq!(current_cpus().unwrap(), before[..1]);
            assert!(pin_current_thread(&before));
            assert_eq!(current_cpus().unwrap(), before);
            assert!(!pin_current_thread(&[]));
            assert!(run_as_batch());
            // SAFETY: reads the calling thread's policy.
            assert_eq!(unsafe { libc::sched_getscheduler(0) }, libc::SCHED_BATCH);
        })
        .join()
        .unwrap();
    }
}
