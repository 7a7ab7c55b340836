//! The `bvol` binary, run as a user would: any arguments, and files of any
//! bytes (or no file, a folder, a device) where it reads one.

use std::io::Read;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use arbitrary::{Result, Unstructured};

use crate::checks::one_line_error;

/// OBJ and trace tokens, for the file the arguments name.
pub const DICTIONARY: &[&[u8]] =
    &[b"v ", b"f ", b"o ", b"\n", b"nan", b"1e38", b"1e-44", b"BPHF", &[1, 0, 0, 0], &[0xff; 4]];

/// How long one run may take before it counts as a hang: the sizes it is
/// given are small, so anything near this is stuck.
pub const TIME_LIMIT: Duration = Duration::from_secs(20);

/// Memory one run may take (`ulimit -d`, in KiB): far more than any input
/// here justifies, far less than an allocation sized from a bad header.
const MEMORY_LIMIT_KIB: u64 = 8 << 20;

static BINARY: OnceLock<PathBuf> = OnceLock::new();

/// Sets the `bvol` binary the `cli` target runs; by default the one
/// `BVOL_FUZZ_BVOL` names, else the one beside the running executable
/// (cargo builds both into the same folder).
pub fn set_binary(path: PathBuf) {
    let _ = BINARY.set(path);
}

fn binary() -> &'static PathBuf {
    BINARY.get_or_init(|| {
        if let Some(path) = std::env::var_os("BVOL_FUZZ_BVOL") {
            return PathBuf::from(path);
        }
        let exe = std::env::current_exe().expect("the running executable's path");
        exe.with_file_name(format!("bvol{}", std::env::consts::EXE_SUFFIX))
    })
}

/// Runs `bvol` with the arguments `data` spells. It ends in time with
/// status 0 or 2 and never panics; status 2 comes with one line naming the
/// file or the argument at fault (or is clap's usage error); status 0
/// prints no NaN, infinity or null.
pub fn run(data: &[u8]) {
    let Ok((args, files)) = arguments(Unstructured::new(data)) else { return };
    let out = run_bvol(&args);
    let (stdout, stderr) =
        (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    let shown = format!("bvol {}", args.join(" "));
    assert!(!stderr.contains("panicked"), "{shown}: panicked: {stderr}");
    match out.status {
        Some(0) => {
            let bad = ["NaN", "nan", "inf", "-inf", "null", "Infinity"];
            let words = stdout.split(|c: char| c.is_whitespace() || ",:[]{}\"".contains(c));
            assert!(!words.into_iter().any(|w| bad.contains(&w)), "{shown}: printed {stdout}");
        }
        // clap's: a usage error, or the help where a subcommand is missing.
        Some(2) if stderr.starts_with("error:") || stderr.contains("\nUsage: ") => {}
        Some(2) => {
            let message =
                stderr.strip_prefix("bvol: ").unwrap_or_else(|| panic!("{shown}: {stderr}"));
            one_line_error(message.trim_end_matches('\n'), None);
            // A loose word may be taken as a file: any argument named counts.
            let mut given = files.iter().chain(&args).filter(|f| !f.is_empty());
            let named = given.any(|f| message.contains(f.as_str()));
            let argument = message.contains("--");
            assert!(named || argument, "{shown}: the error names no file or argument: {message}");
        }
        other => panic!("{shown}: ended with {other:?}: {stderr}"),
    }
}

struct Ran {
    status: Option<i32>,
    stdout: Vec<u8>,
    stderr: Vec<u8>,
}

fn run_bvol(args: &[String]) -> Ran {
    let mut child = Command::new("/bin/sh")
        .arg("-c")
        .arg(format!("ulimit -d {MEMORY_LIMIT_KIB} && exec \"$0\" \"$@\""))
        .arg(binary())
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start bvol");
    let drain = |mut pipe: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            pipe.read_to_end(&mut bytes).map(|_| bytes)
        })
    };
    let stdout = drain(Box::new(child.stdout.take().expect("piped")));
    let stderr = drain(Box::new(child.stderr.take().expect("piped")));
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for bvol") {
            break status;
        }
        if started.elapsed() > TIME_LIMIT {
            let _ = child.kill();
            panic!("bvol {}: still running after {TIME_LIMIT:?}", args.join(" "));
        }
        std::thread::sleep(Duration::from_micros(500));
    };
    let read = |reader: std::thread::JoinHandle<std::io::Result<Vec<u8>>>| {
        reader.join().expect("a pipe reader").expect("read bvol's output")
    };
    let (out, err) = (read(stdout), read(stderr));
    Ran { status: status.code(), stdout: out, stderr: err }
}

/// Arguments, and the files among them; the bytes left over are the file's.
fn arguments(mut u: Unstructured) -> Result<(Vec<String>, Vec<String>)> {
    let u = &mut u;
    let mut args: Vec<String> = Vec::new();
    let mut files = Vec::new();
    let command = u.int_in_range(0u8..=4)?;
    let file = |u: &mut Unstructured, files: &mut Vec<String>| -> Result<String> {
        let path = match u.int_in_range(0u8..=7)? {
            0 => "/no/such/file".to_owned(),
            1 => std::env::temp_dir().display().to_string(),
            2 => "/dev/zero".to_owned(),
            3 => String::new(),
            _ => "FILE".to_owned(), // the input's bytes, written below
        };
        files.push(path.clone());
        Ok(path)
    };
    match command {
        0 => {
            args.push("fit".into());
            if u.arbitrary()? {
                args.push("--json".into());
            }
            args.push(file(u, &mut files)?);
        }
        1 => {
            args.extend(["bench", "pairs", "--load"].map(String::from));
            args.push(file(u, &mut files)?);
            args.extend(["--frames".into(), number(u, 0..=4)?]);
        }
        2 => {
            let scene = *u.choose(&[
                "uniform",
                "clustered",
                "mixed",
                "pile",
                "teleport",
                "flat",
                "heap",
                "ground",
                "fast",
                "wavy",
                "",
            ])?;
            args.extend(["bench", "pairs", "--scene", scene].map(String::from));
            args.extend(["--n".into(), number(u, 0..=300)?, "--frames".into(), number(u, 0..=4)?]);
            args.extend(["--seed".into(), number(u, 0..=u64::MAX)?]);
            if u.arbitrary()? {
                args.push("--events".into());
            }
            if u.ratio(1u8, 4)? {
                args.push("--dump".into());
                args.push(file(u, &mut files)?);
            }
        }
        3 => {
            args.extend(["bench", "world", "--shape"].map(String::from));
            args.push(file(u, &mut files)?);
            args.extend(["--n".into(), number(u, 0..=100)?, "--frames".into(), number(u, 0..=3)?]);
        }
        _ => {
            let words = [
                "fit",
                "bench",
                "pairs",
                "world",
                "--json",
                "--load",
                "--shape",
                "--n",
                "-",
                "--",
                "--help",
                "--version",
                "help",
            ];
            for _ in 0..u.int_in_range(0..=6)? {
                args.push(u.choose(&words)?.to_string());
            }
        }
    }
    if u.ratio(1u8, 3)? {
        args.extend(["--threads".into(), number(u, 0..=1100)?]);
    }
    let bytes = std::mem::replace(u, Unstructured::new(&[])).take_rest();
    let written = crate::scratch::file("cli-input", bytes).display().to_string();
    for f in args.iter_mut().chain(files.iter_mut()).filter(|f| *f == "FILE") {
        *f = written.clone();
    }
    Ok((args, files))
}

/// A number in `range` as text, or text that is not one: negative, past
/// 64 bits, a fraction, a word.
fn number<T>(u: &mut Unstructured, range: std::ops::RangeInclusive<T>) -> Result<String>
where
    T: arbitrary::unstructured::Int + std::fmt::Display,
{
    Ok(match u.int_in_range(0u8..=9)? {
        0 => (*u.choose(&["-1", "18446744073709551616", "1.5", "1e3", "", "ten", "0x10"])?)
            .to_owned(),
        _ => u.int_in_range(range)?.to_string(),
    })
}
