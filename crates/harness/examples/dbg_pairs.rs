use emdstar_harness::pairs::*;
fn main() {
    let s = PairSettings {
        impacts_per_model: 300,
        md_steps_per_contact: vec![25, 50, 100, 200, 400],
        unequal_fraction: 0.3,
        seed: 1,
    };
    let r = sweep(&s, &|| {}).unwrap();
    for i in r.impacts.iter().filter(|i| i.model == "hertz") {
        let e: Vec<String> =
            i.md.iter()
                .map(|m| format!("{:.1e}", m.unwrap().position))
                .collect();
        println!(
            "cdis {:9.2e} ltil {:9.2e} e {:.2} dur {:.2e} dt0 {:.2e} | {}",
            i.c_dis,
            i.l_tilde,
            i.eccentricity,
            i.duration,
            i.md_dt[0],
            e.join(" ")
        );
    }
}
