//! Time the increment reconstruction alone (one thread, the replay's default stencil) on a
//! synthetic 200 Hz record: `segments` alternating between stationary (Earth rate plus sensor
//! noise) and Table 4 pattern 3 angular vibration. Prints ns per interval and a hash of the
//! output bits, so that a change to the kernel can be checked for speed and bit-identity:
//! `cargo run --release -p sins-nav --example reconstruct_speed [samples] [mixed|still|vibrating]`.

use sins_nav::Increment;
use sins_nav::Vec3;
use sins_nav::reconstruct::{IncrementReconstructor, ReconstructConfig};
use std::hash::{Hash, Hasher};

/// A small deterministic generator of uniform deviates in [−1, 1) (xorshift64*).
struct Noise(u64);

impl Noise {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
        x as f64 / (1u64 << 52) as f64 - 1.0
    }
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(2_000_000);
    // Which stretches vibrate: "mixed" (alternate every 500 s), "still" or "vibrating".
    let mode = std::env::args().nth(2).unwrap_or_else(|| "mixed".into());
    let h = 0.005;
    let amp = [8.0f64, 9.0, 15.0].map(f64::to_radians);
    let period = [0.2f64, 0.1, 0.15];
    let mut noise = Noise(0x9e37_79b9_7f4a_7c15);
    let samples: Vec<Increment> = (0..n)
        .map(|k| {
            let t = k as f64 * h;
            let vibrating = match mode.as_str() {
                "still" => false,
                "vibrating" => true,
                _ => (k / 100_000) % 2 == 1,
            };
            let mut rot = |i: usize| {
                let w = std::f64::consts::TAU / period[i];
                let a = if vibrating { amp[i] } else { 0.0 };
                a * ((w * (t + h)).sin() - (w * t).sin()) + 3.6e-7 + 1e-8 * noise.next()
            };
            let dtheta_rad = Vec3::new(rot(0), rot(1), rot(2));
            let dv_mps = Vec3::new(1e-4, -2e-4, 9.8 * h) + Vec3::repeat(1e-7 * noise.next());
            Increment { dtheta_rad, dv_mps }
        })
        .collect();
    let mut r = IncrementReconstructor::new(ReconstructConfig {
        threads: 1,
        ..ReconstructConfig::default()
    });
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    let t0 = std::time::Instant::now();
    let mut take = |r: &mut IncrementReconstructor| {
        while let Some(u) = r.pop() {
            for x in u.phi_rad.iter().chain(u.dv_body_mps.iter()) {
                x.to_bits().hash(&mut hasher);
            }
        }
    };
    for s in &samples {
        r.push(s);
        take(&mut r);
    }
    r.finish();
    take(&mut r);
    let dt = t0.elapsed().as_secs_f64();
    println!(
        "{n} samples {dt:.3} s {:.1} ns/interval hash {:016x}",
        dt / n as f64 * 1e9,
        hasher.finish()
    );
}
