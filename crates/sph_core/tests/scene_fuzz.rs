//! Scene-file fuzzing: thousands of deterministic mutations of every shipped scene (truncations,
//! character flips, numeric extremes, deleted and duplicated keys) each load or are refused,
//! never panic, and never hold more than a bounded amount of memory or time.
//!
//! `sph-bench fuzz-scenes --seed S --count N` runs the same generator for longer.

use sph_core::scene::mutations::{load, mutant};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::Duration;

/// Counts the bytes this test binary holds, and the most it held since the last reset.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let live = LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(live, Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        unsafe { System.dealloc(p, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// The seed and the mutants per shipped scene that CI runs.
const SEED: u64 = 0x5EED_F00D;
const PER_SCENE: u64 = 2000;
/// What one load may hold beyond what the test held before it, and how long it may take. The
/// largest shipped scene builds in well under both; an unbounded allocation or a lattice loop
/// of 1e19 points does not.
const MEMORY_BOUND: usize = 64 << 20;
const TIME_BOUND: Duration = Duration::from_secs(5);

fn shipped_scenes() -> Vec<(String, String)> {
    let dir = format!("{}/../../assets/scenes", env!("CARGO_MANIFEST_DIR"));
    let mut scenes: Vec<(String, String)> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read_to_string(&p).unwrap())
        })
        .collect();
    scenes.sort();
    scenes
}

#[test]
fn mutated_scene_files_load_or_are_refused_within_bounds() {
    // The memory bound is only worth something if the counter sees allocations.
    let base = LIVE.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    drop(std::hint::black_box(vec![0u8; 8 << 20]));
    assert!(PEAK.load(Ordering::Relaxed) - base >= 8 << 20);
    let scenes = shipped_scenes();
    assert!(scenes.len() >= 6, "the shipped scenes: {scenes:?}");
    let (mut loaded, mut refused) = (0u64, 0u64);
    for (name, text) in &scenes {
        for index in 0..PER_SCENE {
            let m = mutant(text, SEED, index);
            let base = LIVE.load(Ordering::Relaxed);
            PEAK.store(base, Ordering::Relaxed);
            let case = format!("{name}, seed {SEED:#x}, mutant {index}: {:?}", m.mutations);
            // On a thread of its own, so that a load that never ends fails the test at the
            // bound instead of hanging CI.
            let (text, file) = (m.text.clone(), name.clone());
            let (send, receive) = mpsc::channel();
            std::thread::spawn(move || {
                let outcome = std::panic::catch_unwind(|| load(&text, &file).map(drop));
                let _ = send.send(outcome);
            });
            let outcome = match receive.recv_timeout(TIME_BOUND) {
                Ok(outcome) => outcome,
                Err(_) => panic!("{case} took more than {TIME_BOUND:?}"),
            };
            let held = PEAK.load(Ordering::Relaxed) - base;
            match outcome {
                Ok(Ok(())) => loaded += 1,
                Ok(Err(e)) => {
                    // A refusal names the file and a field.
                    assert!(e.to_string().starts_with(name.as_str()), "{case}: {e}");
                    assert!(!e.field.is_empty() && !e.message.is_empty(), "{case}: {e}");
                    refused += 1;
                }
                Err(_) => panic!("{case} panicked"),
            }
            assert!(held < MEMORY_BOUND, "{case} held {held} bytes");
        }
    }
    println!(
        "{} mutants (seed {SEED:#x}): {loaded} loaded, {refused} refused",
        loaded + refused
    );
    // The mutations reach past the parser: some still build, most are refused.
    assert!(
        loaded > 0 && refused > loaded,
        "{loaded} loaded, {refused} refused"
    );
}
