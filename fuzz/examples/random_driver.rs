//! A coverage-less fuzz driver on stable Rust: feeds the same targets as the libFuzzer
//! binaries (`dcol_fuzz::shapes`, `dcol_fuzz::queries`) with pseudo-random byte strings, first
//! replaying every file of the checked-in seed corpus (`fuzz/seeds/<target>/`).
//!
//!     cargo run --release --no-default-features --example random_driver -- \
//!         [--target shapes|queries|all] [--inputs N] [--seconds S] [--seed X]
//!     cargo run --release --no-default-features --example random_driver -- \
//!         --target queries --replay FILE    # one saved input, with its full message
//!
//! A panic is a crash: the input is written to `fuzz/artifacts/random_driver/<target>-<hash>`
//! and the driver exits with status 1 after the run. It prints the number of inputs run.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A random input: random length (mostly short), random bytes, sometimes mutated from a
    /// seed input.
    fn input(&mut self, seeds: &[Vec<u8>]) -> Vec<u8> {
        if !seeds.is_empty() && self.next_u64().is_multiple_of(4) {
            let mut v = seeds[(self.next_u64() % seeds.len() as u64) as usize].clone();
            let flips = 1 + self.next_u64() % 8;
            for _ in 0..flips {
                if v.is_empty() {
                    break;
                }
                let i = (self.next_u64() % v.len() as u64) as usize;
                v[i] = self.next_u64() as u8;
            }
            return v;
        }
        let len = match self.next_u64() % 4 {
            0 => self.next_u64() % 32,
            1 | 2 => self.next_u64() % 160,
            _ => self.next_u64() % 1024,
        } as usize;
        (0..len).map(|_| self.next_u64() as u8).collect()
    }
}

type Target = fn(&[u8]);

fn fnv(data: &[u8]) -> u64 {
    data.iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ *b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

fn seeds(dir: &Path) -> Vec<Vec<u8>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.sort();
    files.iter().filter_map(|p| std::fs::read(p).ok()).collect()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .cloned()
    };
    let which = arg("--target").unwrap_or_else(|| "all".into());
    let inputs: u64 = arg("--inputs").map_or(u64::MAX, |v| v.parse().expect("--inputs N"));
    let seconds: f64 = arg("--seconds").map_or(f64::INFINITY, |v| v.parse().expect("--seconds S"));
    let seed: u64 = arg("--seed").map_or(0x00D0_C01F, |v| v.parse().expect("--seed X"));
    if let Some(file) = arg("--replay") {
        let data = std::fs::read(&file).expect("--replay FILE: readable");
        match which.as_str() {
            "shapes" => dcol_fuzz::shapes(&data),
            "queries" => dcol_fuzz::queries(&data),
            _ => {
                eprintln!("--replay needs --target shapes or --target queries");
                std::process::exit(2);
            }
        }
        println!("{file}: no crash");
        return;
    }
    if inputs == u64::MAX && seconds.is_infinite() {
        eprintln!("give --inputs N and/or --seconds S");
        std::process::exit(2);
    }
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let all: [(&str, Target); 2] = [
        ("shapes", dcol_fuzz::shapes),
        ("queries", dcol_fuzz::queries),
    ];
    let targets: Vec<(&str, Target)> = all
        .into_iter()
        .filter(|(n, _)| which == "all" || which == *n)
        .collect();
    if targets.is_empty() {
        eprintln!("unknown target {which}");
        std::process::exit(2);
    }
    // Quiet panics: the driver reports them itself.
    std::panic::set_hook(Box::new(|_| {}));
    let mut crashes = 0u64;
    let mut total = 0u64;
    // One saved input and one line per distinct failure (digits removed from the message).
    let mut seen: std::collections::BTreeMap<String, u64> = Default::default();
    let budget = Duration::from_secs_f64(seconds / targets.len() as f64);
    for (name, target) in &targets {
        let corpus = seeds(&root.join("seeds").join(name));
        let mut rng = Rng(seed ^ fnv(name.as_bytes()));
        let start = Instant::now();
        let mut n = 0u64;
        let mut run = |data: &[u8], n: &mut u64, crashes: &mut u64| {
            *n += 1;
            if let Err(payload) = catch_unwind(AssertUnwindSafe(|| target(data))) {
                *crashes += 1;
                let msg = payload
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                // The invariant's tag ("[prox-nonfinite ...]") and the first shape's kind.
                let tag: String = msg.chars().take_while(|c| *c != ']').collect();
                let rest = msg.get(tag.len() + 1..).unwrap_or("").trim_start();
                let kind: String = rest.chars().take_while(|c| c.is_alphabetic()).collect();
                let sig = format!("{name}: {tag}] {kind}");
                let count = seen.entry(sig).or_insert(0);
                *count += 1;
                if *count == 1 {
                    let dir = root.join("artifacts").join("random_driver");
                    let _ = std::fs::create_dir_all(&dir);
                    let path = dir.join(format!("{name}-{:016x}", fnv(data)));
                    let _ = std::fs::write(&path, data);
                    eprintln!("CRASH in {name} (input saved to {}): {msg}", path.display());
                }
            }
        };
        for s in &corpus {
            run(s, &mut n, &mut crashes);
        }
        while n < inputs && start.elapsed() < budget {
            let data = rng.input(&corpus);
            run(&data, &mut n, &mut crashes);
        }
        println!(
            "{name}: {n} inputs ({} seeds) in {:.1} s",
            corpus.len(),
            start.elapsed().as_secs_f64()
        );
        total += n;
    }
    for (sig, count) in &seen {
        println!("crash x{count}: {sig}");
    }
    println!("total: {total} inputs, {crashes} crashes");
    if crashes > 0 {
        std::process::exit(1);
    }
}
