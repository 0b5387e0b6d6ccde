//! Fuzzing of the readers (issue: nothing crashes): a valid world snapshot
//! and a valid Assembly, serialised to JSON, are mutated at random — a
//! number replaced by an extreme one (0, −1, ±1e300, 1e15, 2⁶⁴, 0.5, a
//! huge exponent), a key deleted or renamed, an array shortened or
//! emptied, a string changed, the text truncated — and read back. The
//! reader must return Ok or a typed error, never panic or abort; a world
//! it accepts must be finite and survive a step (Ok or a typed error).
//!
//! Short run (suite, fixed seed): `cargo test --release --test fuzz_readers`.
//! Long run: `STRANDKIT_FUZZ_SECONDS=600 cargo test --release --test fuzz_readers -- --nocapture`
//! (cases until the time is up, seed from STRANDKIT_FUZZ_SEED or 1).
mod common;
use common::steel_rod;
use nalgebra::Vector3;
use serde_json::Value;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::{Duration, Instant};
use strandkit::prelude::*;

/// SplitMix64: a small deterministic generator (no dependency, fixed seed).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// A world with a bit of everything: two rods (one with roll), a clamp, a
/// link, a slider, loads, a bead, a clip, labels.
fn sample_world() -> World {
    let mut w = World::new(IntegrationParameters { gravity: [0.0, -9.81, 0.0], ..Default::default() });
    let a = w.add_rod(steel_rod(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0), 8, true));
    let b = w.add_rod(steel_rod(Vector3::new(0.0, 0.3, 0.0), Vector3::new(1.0, 0.3, 0.0), 6, false));
    let (a0, a1) = w.rod(a).unwrap().domain();
    let (b0, b1) = w.rod(b).unwrap().domain();
    w.clamp(a, a0, 0.0).unwrap();
    w.add_link(a, b, RelativeDistance { ua: a1, ub: b1, distance: 0.3 }, 1e-6).unwrap();
    w.add_constraint(b, Position { u: b0, axes: [true, true, true, false], target: [0.0, 0.3, 0.0, 0.0] }, 0.0).unwrap();
    w.add_load(Load::PointForce(PointForce { rod: a, u: 0.5 * (a0 + a1), force: [0.0, -10.0, 0.0] })).unwrap();
    w.add_bead(b, 0.5 * (b0 + b1), 0.01, 0.1, 0.005).unwrap();
    w.add_clip([0.5, 0.0, 0.0], 0.05, [0.0, 1.0, 0.0], 100.0).unwrap();
    w.step().unwrap();
    w
}

fn sample_assembly() -> Assembly {
    let mut asm = Assembly::new();
    let a = asm.add_rod(steel_rod(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0), 8, false), Some("rail[0]"));
    let b = asm.add_rod(steel_rod(Vector3::new(0.0, 0.2, 0.0), Vector3::new(1.0, 0.2, 0.0), 8, false), Some("rail[1]"));
    let (u0, u1) = asm.rods[a].rod.domain();
    asm.constrain(a, Position { u: u0, axes: [true, true, true, false], target: [0.0; 4] }).label("pin");
    for i in 0..4 {
        let u = u0 + (u1 - u0) * (i as f64 + 0.5) / 4.0;
        asm.link(a, b, RelativeDistance { ua: u, ub: u, distance: 0.2 }).compliance(1e-6).label(format!("rung[{i}]"));
    }
    asm.add_load(b, PointForce { rod: RodHandle { index: 0, generation: 0 }, u: u1, force: [0.0, 1.0, 0.0] }, Some("pull"));
    asm
}

const NUMBERS: [&str; 10] = ["0", "-1", "1e300", "-1e300", "1e15", "18446744073709551616", "0.5", "1e999", "-0.0", "4294967296"];

/// Every path to a leaf or a container of the JSON tree.
fn paths(v: &Value, here: &mut Vec<Value>, out: &mut Vec<Vec<Value>>) {
    out.push(here.clone());
    match v {
        Value::Object(m) => m.iter().for_each(|(k, x)| {
            here.push(Value::String(k.clone()));
            paths(x, here, out);
            here.pop();
        }),
        Value::Array(a) => a.iter().enumerate().for_each(|(i, x)| {
            here.push(Value::from(i));
            paths(x, here, out);
            here.pop();
        }),
        _ => {}
    }
}

fn at<'a>(v: &'a mut Value, path: &[Value]) -> Option<&'a mut Value> {
    let pointer: String = path
        .iter()
        .map(|k| match k {
            Value::String(s) => format!("/{}", s.replace('~', "~0").replace('/', "~1")),
            other => format!("/{other}"),
        })
        .collect();
    v.pointer_mut(&pointer)
}

/// One random mutation of `text` (1–3 edits of the tree, or a truncation).
fn mutate(text: &str, rng: &mut Rng) -> String {
    if rng.below(8) == 0 {
        let cut = rng.below(text.len());
        return text[..text.floor_char_boundary(cut)].to_string();
    }
    let mut v: Value = serde_json::from_str(text).unwrap();
    let mut raw_numbers = Vec::new();
    for _ in 0..1 + rng.below(3) {
        // Paths anew after each edit (an edit may remove a subtree).
        let mut all = Vec::new();
        paths(&v, &mut Vec::new(), &mut all);
        let p = all[rng.below(all.len())].clone();
        let Some(target) = at(&mut v, &p) else { continue };
        match (rng.below(5), &*target) {
            (0 | 1, Value::Number(_)) | (0, _) => {
                // Numbers as raw text (1e999, 2⁶⁴ do not fit a Value).
                let marker = format!("\"@@{}@@\"", raw_numbers.len());
                raw_numbers.push((marker.clone(), NUMBERS[rng.below(NUMBERS.len())]));
                *target = Value::String(marker.trim_matches('"').to_string());
            }
            (_, Value::Array(a)) if !a.is_empty() => {
                let mut a = a.clone();
                if rng.below(2) == 0 {
                    a.truncate(rng.below(a.len()));
                } else {
                    let i = rng.below(a.len());
                    a.push(a[i].clone());
                }
                *target = Value::Array(a);
            }
            (_, Value::Object(m)) if !m.is_empty() => {
                let mut m = m.clone();
                let k = m.keys().nth(rng.below(m.len())).cloned().unwrap_or_default();
                let x = m.remove(&k).unwrap_or(Value::Null);
                if rng.below(2) == 0 {
                    m.insert(format!("{k}_x"), x);
                }
                *target = Value::Object(m);
            }
            (_, Value::String(_)) => *target = Value::String(["", "Clamped", "Periodic", "nan", "x"][rng.below(5)].into()),
            (_, Value::Bool(b)) => *target = Value::Bool(!b),
            _ => *target = Value::Null,
        }
    }
    let mut out = serde_json::to_string(&v).unwrap();
    for (marker, number) in raw_numbers {
        out = out.replace(&marker, number);
    }
    out
}

/// Reads a mutated snapshot or assembly; panics (the test fails) only if
/// the reader or a step on what it accepted panicked, or accepted a
/// non-finite state.
fn exercise(snapshot: bool, text: &str) -> bool {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        let world = if snapshot {
            World::from_json(text).ok()
        } else {
            Assembly::from_json(text).ok().and_then(|asm| {
                let mut w = World::new(IntegrationParameters::default());
                w.insert(&asm).ok().map(|_| w)
            })
        };
        if let Some(mut w) = world {
            for (_, r) in w.rods() {
                assert!(r.coords().iter().chain(r.velocities()).all(|x| x.is_finite()), "accepted a non-finite rod");
            }
            if w.step().is_ok() {
                for (_, r) in w.rods() {
                    assert!(r.coords().iter().all(|x| x.is_finite()), "a step returned a non-finite state");
                }
            }
            let _ = w.relax();
            return true;
        }
        false
    }));
    match outcome {
        Ok(accepted) => accepted,
        Err(e) => {
            let msg = e.downcast_ref::<String>().cloned().or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()));
            let _ = std::panic::take_hook(); // the report must be seen
            panic!("{} reader panicked on:\n{text}\n{msg:?}", if snapshot { "snapshot" } else { "assembly" });
        }
    }
}

#[test]
fn mutated_snapshots_and_assemblies_never_panic() {
    let seconds: Option<u64> = std::env::var("STRANDKIT_FUZZ_SECONDS").ok().and_then(|s| s.parse().ok());
    let seed: u64 = std::env::var("STRANDKIT_FUZZ_SEED").ok().and_then(|s| s.parse().ok()).unwrap_or(1);
    let texts = [(true, sample_world().to_json().unwrap()), (false, sample_assembly().to_json().unwrap())];
    let mut rng = Rng(seed);
    let deadline = seconds.map(|s| Instant::now() + Duration::from_secs(s));
    let cases = if deadline.is_some() { usize::MAX } else { 300 };
    let (mut n, mut accepted) = (0, 0);
    // Panics are caught and reported by `exercise`; keep their messages quiet.
    std::panic::set_hook(Box::new(|_| {}));
    while n < cases && deadline.is_none_or(|d| Instant::now() < d) {
        let (snapshot, text) = &texts[n % 2];
        accepted += exercise(*snapshot, &mutate(text, &mut rng)) as usize;
        n += 1;
    }
    let _ = std::panic::take_hook();
    println!("{n} mutated inputs read without a panic, {accepted} accepted (seed {seed})");
    assert!(accepted > 0 && accepted < n, "the mutations must exercise both paths");
}
