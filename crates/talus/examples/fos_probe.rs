//! Probe: the criterion's measure per step for trial factors (measurements for docs/stability.md).
use talus::analysis::stability::Analysis;
use talus::scene::Scene;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scene = Scene::from_path(std::path::Path::new(&args[1])).expect("scene");
    let mut a = Analysis::new(&scene)
        .expect("analysis")
        .expect("[stability]");
    let eq = a.equilibrium(&scene).expect("equilibrium");
    println!(
        "equilibrium: {} steps, {} its, {:.2} s, last increment {:.3e}",
        eq.steps, eq.newton_iterations, eq.seconds, eq.last_increment
    );
    for f in args[2..].iter().map(|s| s.parse::<f64>().unwrap()) {
        let t = a.trial(f, &eq.state).unwrap();
        let inc: Vec<String> = t.increments.iter().map(|v| format!("{v:.2e}")).collect();
        println!(
            "F = {f:.4}: {} its {:.2} s err {:?}\n  {}",
            t.newton_iterations,
            t.seconds,
            t.error.as_ref().map(|e| &e[..e.len().min(120)]),
            inc.join(" ")
        );
    }
}
