//! Measures how many `check` calls per second each seed directory allows (no AFL).
use std::time::Instant;
fn main() {
    for (dir, lang, name) in [
        ("seeds/st", plcc_frontend::Lang::St, "f.st"),
        ("seeds/il", plcc_frontend::Lang::Il, "f.il"),
        ("seeds/stl", plcc_frontend::Lang::Stl, "f.stl"),
        ("seeds/ld", plcc_frontend::Lang::Ld, "f.xml"),
    ] {
        let files: Vec<Vec<u8>> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| std::fs::read(e.unwrap().path()).unwrap())
            .collect();
        let t = Instant::now();
        let mut worst = (0f64, 0usize);
        for (i, f) in files.iter().enumerate() {
            let t1 = Instant::now();
            plcc_fuzz::check(f, lang, name);
            let d = t1.elapsed().as_secs_f64();
            if d > worst.0 {
                worst = (d, i);
            }
        }
        let e = t.elapsed().as_secs_f64();
        println!(
            "{dir}: {} files, {:.0} checks/s, worst {:.1} ms",
            files.len(),
            files.len() as f64 / e,
            worst.0 * 1e3
        );
    }
}
