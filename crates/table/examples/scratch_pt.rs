use emdstar_contact::Impact;
use emdstar_table::Table;
use std::hint::black_box;
#[path = "../benches/support/mod.rs"]
mod support;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let table = Table::open(&args[1]).unwrap();
    let m = args[2].as_str();
    let cases = support::impacts(&table, 64, false);
    let info = table.info();
    let range =
        |name: &str| info.box_ranges[info.box_names.iter().position(|x| x == name).unwrap()];
    let mut d = support::Draw(12345);
    let mut imps = Vec::new();
    for _ in 0..4096 {
        imps.push(
            Impact::from_speed_eccentricity(
                d.log_uniform(range("speed")),
                d.log_uniform(range("eccentricity")),
            )
            .unwrap(),
        );
    }
    let (law, pair, _) = &cases[0];
    let pt = table.pair_table(law, pair).unwrap();
    let h = table.pair(law, pair).unwrap();
    let mut best = f64::INFINITY;
    let mut s = 0.0;
    for _ in 0..20 {
        let t0 = support::thread_cpu_ns();
        for im in &imps {
            s += if m == "slice" {
                pt.lookup(black_box(im)).map(|x| x.mor.eps_t).unwrap_or(0.0)
            } else if m == "pair" {
                h.lookup(black_box(im)).map(|x| x.mor.eps_t).unwrap_or(0.0)
            } else if m == "map" {
                h.map()
                    .coords(table.bounds(), black_box(im))
                    .map(|x| x.0.a)
                    .unwrap_or(0.0)
            } else {
                0.0
            };
        }
        best = best.min((support::thread_cpu_ns() - t0) as f64 / imps.len() as f64);
    }
    println!("{m}: {best:.1} ns {s}");
}
