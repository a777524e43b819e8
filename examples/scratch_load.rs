use std::time::Instant;
use tribo::models::thin_film::{example, CavitationSource};
fn main() {
    for eq in ["IV.7", "IV.12", "IV.17", "IV.20"] {
        let f = example(eq).unwrap();
        let n = 1_000_000;
        let t = Instant::now();
        let mut s = 0.0;
        for i in 0..n {
            let x = [(i % 1000) as f64 / 1000.0, (i / 1000) as f64 / 1000.0];
            s += f.reynolds_load(x);
        }
        let a = t.elapsed().as_secs_f64();
        let t = Instant::now();
        for i in 0..n {
            let x = [(i % 1000) as f64 / 1000.0, (i / 1000) as f64 / 1000.0];
            s += f.cavitation_load(x, CavitationSource::Printed);
        }
        let b = t.elapsed().as_secs_f64();
        let t = Instant::now();
        for i in 0..n {
            let x = [(i % 1000) as f64 / 1000.0, (i / 1000) as f64 / 1000.0];
            s += f.gap(x).2;
        }
        let c = t.elapsed().as_secs_f64();
        println!(
            "{eq}: load {:.3} us, cav {:.3} us, gap {:.3} us  ({s})",
            a, b, c
        );
    }
}
