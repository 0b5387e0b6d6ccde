//! Probes of the thermal-noise investigation (issue 16), kept to reproduce
//! its numbers: `cargo run --release --example wlc_probe -- <probe>`, the
//! parameters in environment variables (see each probe).
//!
//! Finding: the dynamics sample the model's Boltzmann distribution (flat
//! measure on control points × e^{−E/kT}) — Metropolis Monte Carlo
//! (`mcfree`) and Langevin (`dyn`) agree to 0.2 % — but that distribution
//! is stiffer than the worm-like chain at coarse resolution: the stretch
//! sampled at 5 Gauss points per segment locks bent cubic segments (⟨R²⟩
//! +3.6 % at h = 7 nm, A = 50 nm, r = 1 nm), short modes are missing
//! (+0.27 h/A), and the flat measure lengthens the contour (⟨ε⟩ ≈
//! 4.3 kT/(S h)). `mcfix` tries two cures of the locking: the B-bar
//! projection of the strain on the spline's axial space, and collocation of
//! the stretch at the Greville points of the derivative space.
#![allow(dead_code)]
use nalgebra::Vector3;
use strandkit::prelude::*;
use strandkit_core::energy::FrameModel;
use strandkit_core::{Scheme, Units};

/// DNA-like rod in molecular units (nm, pN, ns): radius 1 nm, bending
/// persistence `a` nm at 298.15 K, twist persistence `c` nm.
fn dna(length: f64, n_ctrl: usize, a: f64, c: f64, roll: bool) -> Rod {
    dna_r(length, n_ctrl, a, c, roll, 1.0)
}

fn dna_r(length: f64, n_ctrl: usize, a: f64, c: f64, roll: bool, r: f64) -> Rod {
    let kt = Units::Molecular.boltzmann() * 298.15;
    let i = std::f64::consts::PI * r.powi(4) / 4.0;
    let e = a * kt / i;
    let g = c * kt / (2.0 * i);
    let nu = e / (2.0 * g) - 1.0;
    let material = Material::new("dna", e, nu, 1.7e-3).unwrap();
    RodBuilder::straight(Vector3::zeros(), Vector3::new(length, 0.0, 0.0))
        .control_points(n_ctrl)
        .with_roll(roll)
        .section(Section::circle(r).unwrap())
        .material(material)
        .options(RodOptions { model: if roll { FrameModel::Reference } else { FrameModel::Frenet }, ..Default::default() })
        .build()
        .unwrap()
}

fn world(scheme: Scheme, dt: f64, viscosity: f64, seed: u64) -> World {
    let mut w = World::new(IntegrationParameters { dt, scheme, temperature: 298.15, viscosity, units: Units::Molecular, seed, ..Default::default() });
    w.params.divergence_factor = f64::INFINITY;
    w.params.adaptive_dt = true;
    w
}

fn probe_equipartition() {
    let kt = Units::Molecular.boltzmann() * 298.15;
    for scheme in [Scheme::Trapezoidal, Scheme::ImplicitEuler] {
        let mut w = world(scheme, 1e-3, 1.0, 7);
        let mut hs = Vec::new();
        for _ in 0..8 {
            hs.push(w.add_rod(dna(100.0, 20, 50.0, 100.0, true)));
        }
        let ndof: usize = w.rods().map(|(_, r)| r.coords().len()).sum();
        let (mut sum, mut n) = (0.0, 0);
        for k in 0..4000 {
            w.step().unwrap();
            if k >= 500 {
                sum += w.rods().map(|(_, r)| r.kinetic_energy()).sum::<f64>();
                n += 1;
            }
        }
        println!("{scheme:?}: <KE>/(N kT/2) = {:.4}", sum / n as f64 / (0.5 * kt * ndof as f64));
    }
}

fn wlc_r2(a: f64, l: f64) -> f64 {
    2.0 * a * l * (1.0 - a / l * (1.0 - (-l / a).exp()))
}

fn contour_length(rod: &Rod) -> f64 {
    let (u0, u1) = rod.domain();
    let n = 20 * rod.n_segments();
    let p: Vec<Vector3<f64>> = (0..=n).map(|k| rod.position(u0 + (u1 - u0) * k as f64 / n as f64).unwrap()).collect();
    p.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}

fn end_to_end2(rod: &Rod) -> f64 {
    let (u0, u1) = rod.domain();
    (rod.position(u1).unwrap() - rod.position(u0).unwrap()).norm_squared()
}

fn probe_wlc() {
    let args: Vec<f64> = std::env::var("WLC").unwrap_or("50,20,0.01,0.001,20000,8,2".into()).split(',').map(|x| x.parse().unwrap()).collect();
    let (l, n, eta, dt, steps, rods, radius) = (args[0], args[1] as usize, args[2], args[3], args[4] as usize, args[5] as usize, args[6]);
    let mut w = world(Scheme::Trapezoidal, dt, eta, 11);
    w.params.overdamped = std::env::var("OVER").is_ok();
    for _ in 0..rods {
        w.add_rod(dna_r(l, n, 50.0, 100.0, false, radius));
    }
    let t0 = std::time::Instant::now();
    let burn = steps / 5;
    let nb = 10;
    let per = (steps - burn) / nb;
    let mut batches = vec![0.0; nb];
    let mut contour = 0.0;
    let mut subs = 0;
    for k in 0..steps {
        match w.step() {
            Err(e) => panic!("step {k}: {e}"),
            Ok(r) => subs += r.substeps - 1,
        }
        if k >= burn && (k - burn) / per < nb {
            let r2: f64 = w.rods().map(|(_, r)| end_to_end2(r)).sum::<f64>() / rods as f64;
            batches[(k - burn) / per] += r2 / per as f64 / wlc_r2(50.0, l);
            contour += w.rods().map(|(_, r)| contour_length(r)).sum::<f64>() / rods as f64 / l / (per * nb) as f64;
        }
    }
    let m = batches.iter().sum::<f64>() / nb as f64;
    let se = (batches.iter().map(|b| (b - m).powi(2)).sum::<f64>() / (nb * (nb - 1)) as f64).sqrt();
    println!("L={l} n={n} eta={eta} dt={dt} rods={rods} r={radius}: <R²>/WLC = {m:.4} ± {se:.4} contour/L {contour:.4} ({:.1}s, {subs} extra substeps) batches {:?}", t0.elapsed().as_secs_f64(), batches.iter().map(|b| (b * 1000.0).round() / 1000.0).collect::<Vec<_>>());
}

/// Linear check: a clamped cantilever's tip fluctuates with
/// ⟨δy²⟩ = kT L³ / (3B) per transverse axis.
fn probe_cantilever() {
    let args: Vec<f64> = std::env::var("CANT").unwrap_or("50,10,0.01,0.001,20000,8,1".into()).split(',').map(|x| x.parse().unwrap()).collect();
    let (l, n, eta, dt, steps, rods, radius) = (args[0], args[1] as usize, args[2], args[3], args[4] as usize, args[5] as usize, args[6]);
    let kt = Units::Molecular.boltzmann() * 298.15;
    let b = 50.0 * kt;
    let mut w = world(Scheme::Trapezoidal, dt, eta, 5);
    for _ in 0..rods {
        let h = w.add_rod(dna_r(l, n, 50.0, 100.0, false, radius));
        w.clamp(h, 0.0, 0.0).unwrap();
    }
    let burn = steps / 5;
    let (mut s2, mut cnt) = (0.0, 0);
    for k in 0..steps {
        w.step().unwrap();
        if k >= burn {
            for (_, r) in w.rods() {
                let (_, u1) = r.domain();
                let p = r.position(u1).unwrap();
                s2 += 0.5 * (p.y * p.y + p.z * p.z);
            }
            cnt += rods;
        }
    }
    println!("cantilever L={l} n={n}: <dy²> / (kT L³/3B) = {:.4}", s2 / cnt as f64 / (kt * l.powi(3) / (3.0 * b)));
}

/// Metropolis Monte Carlo on the control points (flat measure × e^{−E/kT}):
/// the model's own Boltzmann distribution, without any dynamics.
fn probe_mc_cantilever() {
    let args: Vec<f64> = std::env::var("MC").unwrap_or("20,10,1,2000000,0.3".into()).split(',').map(|x| x.parse().unwrap()).collect();
    let (l, n, radius, sweeps, step) = (args[0], args[1] as usize, args[2], args[3] as usize, args[4]);
    let kt = Units::Molecular.boltzmann() * 298.15;
    let b = 50.0 * kt;
    let mut rod = dna_r(l, n, 50.0, 100.0, false, radius);
    let mut q = rod.coords().to_vec();
    let mut e = rod.elastic_energy();
    let mut state = 12345u64;
    let mut rnd = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut s2, mut cnt, mut acc) = (0.0, 0, 0);
    for k in 0..sweeps {
        // Control points 2.. move freely; 0 fixed; 1 slides along x (clamp).
        let i = 1 + ((rnd() * (n - 1) as f64) as usize).min(n - 2);
        let a = if i == 1 { 0 } else { ((rnd() * 3.0) as usize).min(2) };
        let old = q[i * 3 + a];
        q[i * 3 + a] += step * (2.0 * rnd() - 1.0);
        rod.set_coords(&q).unwrap();
        let e1 = rod.elastic_energy();
        if e1 <= e || rnd() < (-(e1 - e) / kt).exp() {
            e = e1;
            acc += 1;
        } else {
            q[i * 3 + a] = old;
        }
        if k > sweeps / 5 && k % 10 == 0 {
            let t = &q[(n - 1) * 3..];
            s2 += 0.5 * (t[1] * t[1] + t[2] * t[2]);
            cnt += 1;
        }
    }
    rod.set_coords(&q).unwrap();
    println!("MC cantilever L={l} n={n} r={radius}: <dy²>/(kT L³/3B) = {:.4} (acceptance {:.2})", s2 / cnt as f64 / (kt * l.powi(3) / (3.0 * b)), acc as f64 / sweeps as f64);
}


/// Mean and standard error of a correlated series by blocking (Flyvbjerg–
/// Petersen): the largest SE over block levels with ≥ 16 blocks.
fn blocked(x: &[f64]) -> (f64, f64) {
    let m = x.iter().sum::<f64>() / x.len() as f64;
    let mut y = x.to_vec();
    let mut best = 0.0f64;
    while y.len() >= 16 {
        let k = y.len() as f64;
        let mu = y.iter().sum::<f64>() / k;
        let var = y.iter().map(|v| (v - mu).powi(2)).sum::<f64>() / (k - 1.0);
        best = best.max((var / k).sqrt());
        y = y.chunks_exact(2).map(|c| 0.5 * (c[0] + c[1])).collect();
    }
    (m, best)
}

fn env_args(name: &str, default: &str) -> Vec<f64> {
    std::env::var(name).unwrap_or(default.into()).split(',').map(|x| x.parse().unwrap()).collect()
}

fn dna_opts(length: f64, n_ctrl: usize, r: f64, spp: usize, stretch: bool) -> Rod {
    let kt = Units::Molecular.boltzmann() * 298.15;
    let i = std::f64::consts::PI * r.powi(4) / 4.0;
    let e = 50.0 * kt / i;
    let g = 100.0 * kt / (2.0 * i);
    let nu = e / (2.0 * g) - 1.0;
    let material = Material::new("dna", e, nu, 1.7e-3).unwrap();
    let mut opts = RodOptions { model: FrameModel::Frenet, samples_per_segment: spp, ..Default::default() };
    opts.terms.stretch = stretch;
    opts.stretch_at_greville = stretch && std::env::var("GREV").is_ok();
    opts.sampling_length = std::env::var("SL").map(|s| s.parse().unwrap()).unwrap_or(0.0);
    RodBuilder::straight(Vector3::zeros(), Vector3::new(length, 0.0, 0.0))
        .control_points(n_ctrl)
        .with_roll(false)
        .section(Section::circle(r).unwrap())
        .material(material)
        .options(opts)
        .build()
        .unwrap()
}

/// Observables of a free chain from its control points (clamped knots:
/// the curve ends at P0, P_{n-1}, tangents along P1−P0, P_{n-1}−P_{n-2}).
fn chain_obs(q: &[f64], n: usize, l: f64, a: f64) -> (f64, f64, f64) {
    let p = |i: usize| Vector3::new(q[3 * i], q[3 * i + 1], q[3 * i + 2]);
    let r2 = (p(n - 1) - p(0)).norm_squared() / wlc_r2(a, l);
    let t0 = (p(1) - p(0)).normalize();
    let t1 = (p(n - 1) - p(n - 2)).normalize();
    (r2, t0.dot(&t1), 0.0)
}

struct Xs(u64);
impl Xs {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn unit(&mut self) -> Vector3<f64> {
        loop {
            let v = Vector3::new(2.0 * self.next() - 1.0, 2.0 * self.next() - 1.0, 2.0 * self.next() - 1.0);
            let n = v.norm_squared();
            if n > 1e-6 && n <= 1.0 {
                return v / n.sqrt();
            }
        }
    }
}

/// Metropolis MC of a FREE chain on the model's own Boltzmann distribution
/// (flat measure on control points × e^{−E/kT}): pivot moves (rotate the
/// control points on one side of P_k about P_k: an isometry, Jacobian 1,
/// symmetric) plus single-point translations. MCF="L,n,r,moves,spp,seed".
fn probe_mc_free() {
    let args = env_args("MCF", "50,10,1,2000000,5,1");
    let (l, n, radius, moves, spp, seed) = (args[0], args[1] as usize, args[2], args[3] as usize, args[4] as usize, args[5] as u64);
    let a_p = 50.0;
    let kt = Units::Molecular.boltzmann() * 298.15;
    let mut rod = dna_opts(l, n, radius, spp, true);
    let mut bend = dna_opts(l, n, radius, spp, false);
    let q = rod.coords().to_vec();
    let mut crod = rod.clone();
    let m = metropolis(q, n, l, a_p, moves, seed, kt, |q| {
        rod.set_coords(q).unwrap();
        bend.set_coords(q).unwrap();
        (rod.elastic_energy(), bend.elastic_energy())
    }, &mut crod);
    println!(
        "MCfree L={l} n={n} r={radius} spp={spp} moves={moves}: <R²>/WLC = {:.4} ± {:.4}  <t0·tL> = {:.4} ± {:.4} (WLC {:.4})  <Eb>/kT = {:.3} ± {:.3}  <Es>/kT = {:.3} ± {:.3}  contour/L {:.5}  {}",
        m.r2.0, m.r2.1, m.tt.0, m.tt.1, (-l / a_p).exp(), m.eb.0, m.eb.1, m.es.0, m.es.1, m.contour, m.tuning
    );
}

/// What [`metropolis`] measured: (mean, blocked error) of ⟨R²⟩/WLC, t0·tL,
/// bending and stretch energies / kT; the mean contour / L; the moves' tuning.
struct McStats {
    r2: (f64, f64),
    tt: (f64, f64),
    eb: (f64, f64),
    es: (f64, f64),
    contour: f64,
    tuning: String,
}

/// Metropolis MC of a free chain from control points `q` (3 per point):
/// [`propose`]'s moves, step sizes tuned to 40 % acceptance during the
/// first fifth (discarded), `energy(q)` = (total, bending); observables
/// every `n` moves, the contour (on `crod`) every 200 samples.
#[allow(clippy::too_many_arguments)]
fn metropolis(mut q: Vec<f64>, n: usize, l: f64, a_p: f64, moves: usize, seed: u64, kt: f64, mut energy: impl FnMut(&[f64]) -> (f64, f64), crod: &mut Rod) -> McStats {
    let (mut e, _) = energy(&q);
    let mut rng = Xs(0x9E3779B97F4A7C15 ^ seed.wrapping_mul(0x2545F4914F6CDD1D));
    let mut piv = 0.2f64;
    let h = l / (n - 3) as f64;
    let mut loc = 0.02 * h;
    let burn = moves / 5;
    let (mut acc_p, mut try_p, mut acc_l, mut try_l) = (0usize, 0usize, 0usize, 0usize);
    let (mut r2s, mut tts, mut ebs, mut ess) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut contour = (0.0, 0);
    let t0 = std::time::Instant::now();
    let mut qn = q.clone();
    for k in 0..moves {
        let pivot = propose(&mut rng, &q, &mut qn, n, piv, loc);
        if pivot {
            try_p += 1;
        } else {
            try_l += 1;
        }
        let (e1, _) = energy(&qn);
        if e1 <= e || rng.next() < (-(e1 - e) / kt).exp() {
            e = e1;
            q.copy_from_slice(&qn);
            if pivot {
                acc_p += 1
            } else {
                acc_l += 1
            }
        }
        if k < burn && k % 2000 == 1999 {
            let (fp, fl) = (acc_p as f64 / try_p.max(1) as f64, acc_l as f64 / try_l.max(1) as f64);
            piv *= if fp > 0.4 { 1.1 } else { 0.9 };
            loc *= if fl > 0.4 { 1.1 } else { 0.9 };
            piv = piv.min(1.0);
            (acc_p, try_p, acc_l, try_l) = (0, 0, 0, 0);
        }
        if k >= burn && k % n == 0 {
            let (r2, tt, _) = chain_obs(&q, n, l, a_p);
            r2s.push(r2);
            tts.push(tt);
            let (et, eb) = energy(&q);
            ebs.push(eb / kt);
            ess.push((et - eb) / kt);
            if r2s.len() % 200 == 0 {
                crod.set_coords(&q).unwrap();
                contour.0 += contour_length(crod) / l;
                contour.1 += 1;
            }
        }
    }
    let tuning = format!(
        "acc p {:.2} (piv {piv:.3}) l {:.2} (loc {loc:.4})  {:.1}s",
        acc_p as f64 / try_p.max(1) as f64,
        acc_l as f64 / try_l.max(1) as f64,
        t0.elapsed().as_secs_f64()
    );
    McStats { r2: blocked(&r2s), tt: blocked(&tts), eb: blocked(&ebs), es: blocked(&ess), contour: contour.0 / contour.1.max(1) as f64, tuning }
}

/// Langevin dynamics of free chains with blocking errors. WLD="L,n,eta,dt,steps,rods,r,burnfrac,seed".
fn probe_wlc_dyn() {
    let args = env_args("WLD", "50,10,0.01,0.001,100000,16,1,0.1,11");
    let (l, n, eta, dt, steps, rods, radius, bf, seed) = (args[0], args[1] as usize, args[2], args[3], args[4] as usize, args[5] as usize, args[6], args[7], args[8] as u64);
    let kt = Units::Molecular.boltzmann() * 298.15;
    let mut w = world(Scheme::Trapezoidal, dt, eta, seed);
    let spp = std::env::var("SPP").map(|s| s.parse().unwrap()).unwrap_or(5);
    for _ in 0..rods {
        w.add_rod(dna_opts(l, n, radius, spp, true));
    }
    let mut bend = dna_opts(l, n, radius, spp, false);
    let t0 = std::time::Instant::now();
    let burn = (steps as f64 * bf) as usize;
    let (mut r2s, mut tts, mut ebs, mut ess, mut trace, mut lcs) = (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let rec = 10;
    for k in 0..steps {
        w.step().unwrap();
        if k % rec == 0 {
            let (mut r2, mut tt, mut eb, mut es) = (0.0, 0.0, 0.0, 0.0);
            for (_, r) in w.rods() {
                let o = chain_obs(r.coords(), n, l, 50.0);
                r2 += o.0 / rods as f64;
                tt += o.1 / rods as f64;
                bend.set_coords(r.coords()).unwrap();
                let b = bend.elastic_energy();
                eb += b / kt / rods as f64;
                es += (r.elastic_energy() - b) / kt / rods as f64;
            }
            trace.push(r2);
            if k >= burn && k % (10 * rec) == 0 {
                lcs.push(w.rods().map(|(_, r)| contour_length(r)).sum::<f64>() / rods as f64);
            }
            if k >= burn {
                r2s.push(r2);
                tts.push(tt);
                ebs.push(eb);
                ess.push(es);
            }
        }
    }
    let (r2, r2e) = blocked(&r2s);
    let (tt, tte) = blocked(&tts);
    let (eb, ebe) = blocked(&ebs);
    let (es, ese) = blocked(&ess);
    // R² trace in 10 windows of the whole run (burn-in included)
    let nw = trace.len() / 10;
    let win: Vec<f64> = trace.chunks(nw).take(10).map(|c| (c.iter().sum::<f64>() / c.len() as f64 * 1000.0).round() / 1000.0).collect();
    let lc = lcs.iter().sum::<f64>() / lcs.len() as f64;
    println!("contour/L = {:.4}; <R²>/WLC(Lc) = {:.4}", lc / l, r2 * wlc_r2(50.0, l) / wlc_r2(50.0, lc));
    println!(
        "DYN L={l} n={n} r={radius} spp={spp} eta={eta} dt={dt} steps={steps} rods={rods}: <R²>/WLC = {r2:.4} ± {r2e:.4}  <t0·tL> = {tt:.4} ± {tte:.4} (WLC {:.4})  <Eb>/kT = {eb:.3} ± {ebe:.3}  <Es>/kT = {es:.3} ± {ese:.3}  {:.1}s  windows {win:?}",
        (-l / 50.0).exp(),
        t0.elapsed().as_secs_f64()
    );
}

/// A stretch energy computed here (not by the core) on a rod's spline:
/// ε_g = |r'(u_g)|/|r0'(u_g)| − 1 at `pts` Gauss points per segment, then
/// either the core's ½ S Σ w ε² (mode 0, a check), or the B-bar energy
/// ½ S εᵀ W Φ (ΦᵀWΦ)⁺ ΦᵀW ε (mode 1): ε projected in L² onto the axial
/// strains the spline can represent, span{N_i'(u)/|r0'(u)|} (dim n−1), so
/// bending-induced strain outside that space costs nothing (no locking).
struct StretchX {
    ctrl: Vec<[usize; 4]>,
    d1: Vec<[f64; 4]>,
    speed0: Vec<f64>,
    k: nalgebra::DMatrix<f64>,
    s: f64,
}

impl StretchX {
    fn new(rod: &Rod, pts: usize, s: f64, bbar: bool) -> StretchX {
        let (gx, gw) = strandkit_core::quadrature::gauss_legendre(pts).unwrap();
        let (u0, u1) = rod.domain();
        let nseg = rod.n_segments();
        let n = rod.n_ctrl();
        let (mut ctrl, mut d1, mut speed0, mut w) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let q0 = rod.rest_coords();
        for seg in 0..nseg {
            let (a, b) = (u0 + (u1 - u0) * seg as f64 / nseg as f64, u0 + (u1 - u0) * (seg + 1) as f64 / nseg as f64);
            for (x, wt) in gx.iter().zip(gw.iter()) {
                let u = 0.5 * (a + b) + 0.5 * (b - a) * x;
                let speed = push_point(rod, q0, u, &mut ctrl, &mut d1, &mut speed0);
                w.push(wt * 0.5 * (b - a) * speed);
            }
        }
        let m = w.len();
        let k = if bbar {
            let mut phi = nalgebra::DMatrix::zeros(m, n);
            for g in 0..m {
                for k in 0..4 {
                    phi[(g, ctrl[g][k])] += d1[g][k] / speed0[g];
                }
            }
            let wm = nalgebra::DMatrix::from_diagonal(&nalgebra::DVector::from_vec(w.clone()));
            let g = phi.transpose() * &wm * &phi;
            let gn = g.norm();
            let gp = g.pseudo_inverse(1e-10 * gn).unwrap();
            &wm * &phi * gp * phi.transpose() * &wm
        } else {
            nalgebra::DMatrix::from_diagonal(&nalgebra::DVector::from_vec(w.clone()))
        };
        StretchX { ctrl, d1, speed0, k, s }
    }
    /// Greville collocation of the stretch: ε at the n−1 Greville abscissae
    /// of the quadratic (derivative) spline space, i.e. the two ends and
    /// every segment midpoint, weighted by ∫ψ_j ds0 (ψ_j the quadratic
    /// B-splines, uniform clamped knots): as many stretch samples as axial
    /// strain modes, local (one sample per segment + ends).
    fn greville(rod: &Rod, s: f64) -> StretchX {
        let (u0, u1) = rod.domain();
        let m = rod.n_segments();
        let n = rod.n_ctrl();
        assert!((u1 - u0 - m as f64).abs() < 1e-12, "unit knot spans expected");
        let mut t = vec![0.0; 3];
        t.extend((1..m).map(|i| i as f64));
        t.extend([m as f64; 3]);
        let q0 = rod.rest_coords();
        let (mut ctrl, mut d1, mut speed0, mut w) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for j in 0..n - 1 {
            let xi = 0.5 * (t[j + 1] + t[j + 2]);
            let wt = (t[j + 3] - t[j]) / 3.0;
            let u = (u0 + xi).clamp(u0, u1);
            let speed = push_point(rod, q0, u, &mut ctrl, &mut d1, &mut speed0);
            w.push(wt * speed);
        }
        let k = nalgebra::DMatrix::from_diagonal(&nalgebra::DVector::from_vec(w));
        StretchX { ctrl, d1, speed0, k, s }
    }
    fn energy(&self, q: &[f64]) -> f64 {
        let m = self.ctrl.len();
        let mut eps = nalgebra::DVector::zeros(m);
        for g in 0..m {
            let mut r1 = Vector3::zeros();
            for k in 0..4 {
                let i = self.ctrl[g][k];
                r1 += self.d1[g][k] * Vector3::new(q[3 * i], q[3 * i + 1], q[3 * i + 2]);
            }
            eps[g] = r1.norm() / self.speed0[g] - 1.0;
        }
        0.5 * self.s * eps.dot(&(&self.k * &eps))
    }
}

/// MC of a free chain with bend from the core (stretch off) and stretch
/// from [`StretchX`]. MCX="L,n,r,moves,mode,seed,pts" (mode 0 core-like, 1 B-bar).
fn probe_mc_fix() {
    let args = env_args("MCX", "50,10,1,2000000,1,1,5");
    let (l, n, radius, moves, mode, seed, pts) = (args[0], args[1] as usize, args[2], args[3] as usize, args[4] as usize, args[5] as u64, args[6] as usize);
    let a_p = 50.0;
    let kt = Units::Molecular.boltzmann() * 298.15;
    let s_mod = 200.0 * kt / (radius * radius); // S = E π r², E = A kT / I
    let full = dna_opts(l, n, radius, 5, true);
    let mut bend = dna_opts(l, n, radius, 5, false);
    let st = if mode == 2 { StretchX::greville(&bend, s_mod) } else { StretchX::new(&bend, pts, s_mod, mode == 1) };
    let check = StretchX::new(&bend, 5, s_mod, false);
    // check mode 0 against the core on a random shape
    {
        let mut rng = Xs(99);
        let q: Vec<f64> = full.coords().iter().map(|x| x + 0.3 * (2.0 * rng.next() - 1.0)).collect();
        let mut f2 = full.clone();
        f2.set_coords(&q).unwrap();
        bend.set_coords(&q).unwrap();
        println!("check: core stretch {:.6e} here {:.6e}", f2.elastic_energy() - bend.elastic_energy(), check.energy(&q));
    }
    let q = full.coords().to_vec();
    let energy = |bend: &mut Rod, q: &[f64]| -> (f64, f64) {
        bend.set_coords(q).unwrap();
        let eb = bend.elastic_energy();
        (eb + st.energy(q), eb)
    };
    let mut crod = full.clone();
    let m = metropolis(q, n, l, a_p, moves, seed, kt, |q| energy(&mut bend, q), &mut crod);
    let c = m.contour;
    println!(
        "MCfix mode={mode} pts={pts} L={l} n={n} r={radius} moves={moves}: <R²>/WLC = {:.4} ± {:.4} (÷WLC(contour): {:.4})  <t0·tL> = {:.4} ± {:.4} (WLC {:.4}, at contour {:.4})  <Eb>/kT = {:.3} ± {:.3}  <Es>/kT = {:.3} ± {:.3}  contour/L {c:.5}  {}",
        m.r2.0,
        m.r2.1,
        m.r2.0 * wlc_r2(a_p, l) / wlc_r2(a_p, c * l),
        m.tt.0,
        m.tt.1,
        (-l / a_p).exp(),
        (-c * l / a_p).exp(),
        m.eb.0,
        m.eb.1,
        m.es.0,
        m.es.1,
        m.tuning
    );
}

/// Pure bending in a plane: minimise the energy over the control points with
/// the start tangent along +x and the end tangent at angle Φ (free ends
/// otherwise), compare with the exact ½ B Φ²/L. ARC="L,n,r,mode" (mode 0
/// core stretch, 1 B-bar stretch). Newton with finite-difference Hessian.
fn probe_arc() {
    let args = env_args("ARC", "50,10,1,0");
    let (l, n, radius, mode) = (args[0], args[1] as usize, args[2], args[3] as usize);
    let kt = Units::Molecular.boltzmann() * 298.15;
    let b = 50.0 * kt;
    let s_mod = 200.0 * kt / (radius * radius);
    let mut full = dna_opts(l, n, radius, 5, true);
    let mut bend = dna_opts(l, n, radius, 5, false);
    let bb = if mode == 2 { StretchX::greville(&bend, s_mod) } else { StretchX::new(&bend, 5, s_mod, true) };
    let nv = 2 * n - 4;
    for &phi in &[0.25f64, 0.5, 1.0, 2.0, 3.0, 4.5, 6.0] {
        let (c, sn) = (phi.cos(), phi.sin());
        let to_q = |x: &[f64]| -> Vec<f64> {
            let mut q = vec![0.0; 3 * n];
            q[3] = x[0];
            for i in 2..n - 2 {
                q[3 * i] = x[2 + 2 * (i - 2)];
                q[3 * i + 1] = x[3 + 2 * (i - 2)];
            }
            let (ex, ey) = (x[nv - 2], x[nv - 1]);
            q[3 * (n - 1)] = ex;
            q[3 * (n - 1) + 1] = ey;
            q[3 * (n - 2)] = ex - x[1] * c;
            q[3 * (n - 2) + 1] = ey - x[1] * sn;
            q
        };
        let mut energy = |x: &[f64]| -> (f64, f64) {
            let q = to_q(x);
            bend.set_coords(&q).unwrap();
            let eb = bend.elastic_energy();
            let es = if mode >= 1 {
                bb.energy(&q)
            } else {
                full.set_coords(&q).unwrap();
                full.elastic_energy() - eb
            };
            (eb + es, eb)
        };
        // initial guess: control points on the arc at their rest arc lengths
        let rad = l / phi;
        let q0 = dna_opts(l, n, radius, 5, true).rest_coords().to_vec();
        let arc = |s: f64| Vector3::new(rad * (s / rad).sin(), rad * (1.0 - (s / rad).cos()), 0.0);
        let mut x = vec![0.0; nv];
        x[0] = q0[3];
        for i in 2..n - 2 {
            let p = arc(q0[3 * i]);
            x[2 + 2 * (i - 2)] = p.x;
            x[3 + 2 * (i - 2)] = p.y;
        }
        let pe = arc(l);
        x[1] = l - q0[3 * (n - 2)];
        x[nv - 2] = pe.x;
        x[nv - 1] = pe.y;
        fd_newton(&mut x, &mut |y: &[f64]| energy(y).0, 1e-4);
        let (e, eb) = energy(&x);
        let exact = 0.5 * b * phi * phi / l;
        let q = to_q(&x);
        full.set_coords(&q).unwrap();
        let h = l / (n - 3) as f64;
        println!(
            "arc mode={mode} L={l} n={n} r={radius} Φ={phi} (κh = {:.3}): E/E_exact = {:.4}  (bend {:.4}, stretch {:.4})  contour/L {:.5}",
            phi / l * h,
            e / exact,
            eb / exact,
            (e - eb) / exact,
            contour_length(&full) / l
        );
    }
}

/// Minimise f over x by Newton with a finite-difference Hessian (small n).
fn fd_newton(x: &mut Vec<f64>, f: &mut dyn FnMut(&[f64]) -> f64, d: f64) {
    let nv = x.len();
    for _ in 0..100 {
        let e0 = f(x);
        let mut g = nalgebra::DVector::zeros(nv);
        let mut hm = nalgebra::DMatrix::zeros(nv, nv);
        let (mut ep, mut em) = (vec![0.0; nv], vec![0.0; nv]);
        for i in 0..nv {
            let mut y = x.clone();
            y[i] += d;
            ep[i] = f(&y);
            y[i] -= 2.0 * d;
            em[i] = f(&y);
            g[i] = (ep[i] - em[i]) / (2.0 * d);
            hm[(i, i)] = (ep[i] - 2.0 * e0 + em[i]) / (d * d);
        }
        for i in 0..nv {
            for j in 0..i {
                let mut y = x.clone();
                y[i] += d;
                y[j] += d;
                let v = (f(&y) - ep[i] - ep[j] + e0) / (d * d);
                hm[(i, j)] = v;
                hm[(j, i)] = v;
            }
        }
        let scale = (0..nv).map(|i| hm[(i, i)].abs()).fold(0.0f64, f64::max);
        let mut lam = 0.0;
        let step = loop {
            let mut hl = hm.clone();
            for i in 0..nv {
                hl[(i, i)] += lam;
            }
            if let Some(ch) = hl.cholesky() {
                break ch.solve(&g);
            }
            lam = if lam == 0.0 { 1e-8 * scale } else { lam * 10.0 };
        };
        let mut t = 1.0;
        loop {
            let y: Vec<f64> = x.iter().zip(step.iter()).map(|(a, s)| a - t * s).collect();
            if f(&y) <= e0 || t < 1e-8 {
                *x = y;
                break;
            }
            t *= 0.5;
        }
        if g.norm() < 1e-12 * scale.max(1.0) {
            break;
        }
    }
}

/// A stretch sample at `u`: its control points, basis derivatives and rest
/// speed |r0′(u)| (returned too), from the rest coordinates `q0`.
fn push_point(rod: &Rod, q0: &[f64], u: f64, ctrl: &mut Vec<[usize; 4]>, d1: &mut Vec<[f64; 4]>, speed0: &mut Vec<f64>) -> f64 {
    let (c, bas) = rod.basis_at(u).unwrap();
    let mut r1 = Vector3::zeros();
    for k in 0..4 {
        r1 += bas[1][k] * Vector3::new(q0[3 * c[k]], q0[3 * c[k] + 1], q0[3 * c[k] + 2]);
    }
    ctrl.push(c);
    d1.push(bas[1]);
    speed0.push(r1.norm());
    r1.norm()
}

/// Locking of a short-wavelength bending mode: transverse control-point
/// displacements y_i = a sin(π k i/(n−1)) held, the axial coordinates x_i
/// (i ≥ 1) relaxed; E_min(a) with the core stretch and with B-bar.
/// MODE="L,n,r,k".
fn probe_mode() {
    let args = env_args("MODE", "50,10,1,6");
    let (l, n, radius, km) = (args[0], args[1] as usize, args[2], args[3]);
    let kt = Units::Molecular.boltzmann() * 298.15;
    let s_mod = 200.0 * kt / (radius * radius);
    let mut full = dna_opts(l, n, radius, 5, true);
    let mut bend = dna_opts(l, n, radius, 5, false);
    let bb = StretchX::new(&bend, 5, s_mod, true);
    let q0 = full.rest_coords().to_vec();
    let mut k0 = [0.0; 2];
    let mut a_th = 0.0;
    for (ia, &a) in [1e-3f64, 0.25, 0.5, 1.0, 1.5, 2.0, 3.0].iter().enumerate() {
        let mut out = [0.0; 2];
        let mut esh = [0.0; 2];
        for mode in 0..2 {
            let mut energy = |x: &[f64]| -> (f64, f64) {
                let mut q = q0.clone();
                for i in 0..n {
                    q[3 * i + 1] = a * (std::f64::consts::PI * km * i as f64 / (n - 1) as f64).sin();
                    if i >= 1 {
                        q[3 * i] = x[i - 1];
                    }
                }
                bend.set_coords(&q).unwrap();
                let eb = bend.elastic_energy();
                let es = if mode == 1 {
                    bb.energy(&q)
                } else {
                    full.set_coords(&q).unwrap();
                    full.elastic_energy() - eb
                };
                (eb + es, es)
            };
            let mut x: Vec<f64> = (1..n).map(|i| q0[3 * i]).collect();
            fd_newton(&mut x, &mut |y| energy(y).0, 1e-5);
            let (e, es) = energy(&x);
            out[mode] = e / (a * a);
            esh[mode] = es / e;
        }
        if ia == 0 {
            k0 = out;
            a_th = (kt / (2.0 * out[0])).sqrt();
            println!("mode k={km} L={l} n={n} r={radius}: small-a stiffness 2E/a² core {:.4e} bbar {:.4e}; thermal amplitude a_th = {a_th:.3} nm", 2.0 * out[0], 2.0 * out[1]);
            continue;
        }
        println!(
            "  a = {a:.2} nm ({:.2} a_th): E/E_harmonic core {:.4} (stretch share {:.3})  bbar {:.4} (stretch share {:.3})",
            a / a_th,
            out[0] / k0[0],
            esh[0],
            out[1] / k0[1],
            esh[1]
        );
    }
}

/// A Metropolis proposal on the control polygon `q` (3 coordinates per
/// point) into `qn`: half the time a pivot (one side rotated about a
/// control point by up to `piv` rad; Jacobian 1, symmetric), else one
/// point moved by up to `loc` per axis. Returns whether it pivoted.
fn propose(rng: &mut Xs, q: &[f64], qn: &mut [f64], n: usize, piv: f64, loc: f64) -> bool {
    qn.copy_from_slice(q);
    let pivot = rng.next() < 0.5;
    if pivot {
        let c = ((rng.next() * n as f64) as usize).min(n - 1);
        let tail = rng.next() < 0.5;
        let axis = rng.unit();
        let ang = piv * (2.0 * rng.next() - 1.0);
        let rot = nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_unchecked(axis), ang);
        let pc = Vector3::new(q[3 * c], q[3 * c + 1], q[3 * c + 2]);
        let range: Vec<usize> = if tail { (c + 1..n).collect() } else { (0..c).collect() };
        for j in range {
            let pj = Vector3::new(q[3 * j], q[3 * j + 1], q[3 * j + 2]);
            let v = pc + rot * (pj - pc);
            qn[3 * j..3 * j + 3].copy_from_slice(v.as_slice());
        }
    } else {
        let i = ((rng.next() * n as f64) as usize).min(n - 1);
        for a in 0..3 {
            qn[3 * i + a] += loc * (2.0 * rng.next() - 1.0);
        }
    }
    pivot
}

fn main() {
    match std::env::args().nth(1).as_deref() {
        Some("equipartition") => probe_equipartition(),
        Some("wlc") => probe_wlc(),
        Some("cantilever") => probe_cantilever(),
        Some("mc") => probe_mc_cantilever(),
        Some("mcfree") => probe_mc_free(),
        Some("dyn") => probe_wlc_dyn(),
        Some("mcfix") => probe_mc_fix(),
        Some("arc") => probe_arc(),
        Some("mode") => probe_mode(),
        _ => eprintln!("usage: wlc_probe equipartition|wlc|cantilever|mc|mcfree|dyn|mcfix|arc|mode"),
    }
}
