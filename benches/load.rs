//! Load benchmark (not a test): evaluate the Reynolds loads l_R (II.37) and l_{R,c} (II.39)
//! from the general Chapter I formulas at 250 000 points for each fluid example, one thread,
//! and print nanoseconds per point and a checksum (to compare two builds bitwise).
//!
//! `cargo bench --bench load`

use std::time::Instant;

use tribo::models::thin_film::{example, CavitationSource, EXAMPLES};

fn main() {
    let n = 500usize;
    let mut total = 0.0;
    for label in EXAMPLES {
        let film = example(label).expect("known example");
        let t = Instant::now();
        let mut sum = 0.0;
        let mut bits = 0u64;
        for i in 0..n {
            for j in 0..n {
                let x = [(i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64];
                let l = film.reynolds_load(x) + film.cavitation_load(x, CavitationSource::Printed);
                sum += l;
                bits = bits.rotate_left(5) ^ (l + 0.0).to_bits(); // + 0.0: −0 → +0
            }
        }
        let s = t.elapsed().as_secs_f64();
        total += s;
        println!(
            "({label:>5}) {:>7.1} ns per point (both loads)  sum {sum:.12e}  bits {bits:016x}",
            1e9 * s / (n * n) as f64
        );
    }
    println!("total {total:.3} s");
}
