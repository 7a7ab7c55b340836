//! The runner's guards, each made to fire by a target that misbehaves on
//! purpose: a panic, an allocation past the cap, a run past the time limit.

use std::path::PathBuf;
use std::process::Command;
use std::time::Duration;

use bvol_fuzz::Target;
use bvol_fuzz::cap::CappedAlloc;
use bvol_fuzz::runner::{self, BASE_MEMORY};

#[global_allocator]
static ALLOC: CappedAlloc = CappedAlloc;

const SECOND: Duration = Duration::from_secs(1);

fn found() -> PathBuf {
    let folder = std::env::var_os("GUARDS_FOUND").map(PathBuf::from);
    folder
        .unwrap_or_else(|| std::env::temp_dir().join(format!("bvol-guards-{}", std::process::id())))
}

fn panics_on_boom(input: &[u8]) {
    assert_ne!(input, b"boom", "the input was boom");
}

/// Asks for twice the cap on `more`, a quarter of it otherwise; a refusal
/// is not a panic here, so only the allocation hook can tell.
fn allocates(input: &[u8]) {
    let size = if input == b"more" { 2 * BASE_MEMORY } else { BASE_MEMORY / 4 };
    let mut bytes: Vec<u8> = Vec::new();
    let granted = bytes.try_reserve_exact(size).is_ok();
    assert_eq!(granted, input != b"more", "the cap let {size} bytes through or refused them");
}

fn sleeps(_: &[u8]) {
    std::thread::sleep(10 * SECOND);
}

static PANICS: Target =
    Target { name: "panics", run: panics_on_boom, max_len: 8, dictionary: &[], time: SECOND };
static ALLOCATES: Target =
    Target { name: "allocates", run: allocates, max_len: 8, dictionary: &[], time: SECOND };
static SLEEPS: Target = Target {
    name: "sleeps",
    run: sleeps,
    max_len: 8,
    dictionary: &[],
    time: Duration::from_millis(100),
};

#[test]
fn a_panic_fails_the_input_and_saves_it() {
    runner::install_guards(found());
    assert!(runner::run_one(&PANICS, b"calm", true));
    assert!(!runner::saved_path("panics", b"calm").exists());
    assert!(!runner::run_one(&PANICS, b"boom", true));
    assert_eq!(std::fs::read(runner::saved_path("panics", b"boom")).unwrap(), b"boom");
}

#[test]
fn an_allocation_past_the_cap_is_refused_and_saves_the_input() {
    runner::install_guards(found());
    assert!(runner::run_one(&ALLOCATES, b"less", true));
    assert!(!runner::saved_path("allocates", b"less").exists());
    assert!(runner::run_one(&ALLOCATES, b"more", true));
    assert_eq!(std::fs::read(runner::saved_path("allocates", b"more")).unwrap(), b"more");
}

/// Run in a child process, as the watchdog ends the process it runs in.
#[test]
fn a_run_past_its_limit_ends_the_process_and_saves_the_input() {
    if std::env::var_os("GUARDS_CHILD").is_some() {
        runner::install_guards(found());
        runner::run_one(&SLEEPS, b"nap", true);
        panic!("the watchdog let a 10 s run through");
    }
    let folder = std::env::temp_dir().join(format!("bvol-guards-child-{}", std::process::id()));
    let out = Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "a_run_past_its_limit_ends_the_process_and_saves_the_input",
            "--nocapture",
        ])
        .env("GUARDS_CHILD", "1")
        .env("GUARDS_FOUND", &folder)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("ran past its time limit"), "{stderr}");
    assert_eq!(std::fs::read(folder.join("sleeps").join(name_of(b"nap"))).unwrap(), b"nap");
}

/// The file name a saved input gets: its hash, as the runner names it.
fn name_of(input: &[u8]) -> String {
    runner::install_guards(found());
    let path = runner::saved_path("sleeps", input);
    path.file_name().unwrap().to_string_lossy().into_owned()
}
