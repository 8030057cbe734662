//! Scratch: altitude lost from the seven hover half turns for scenario files.
fn main() -> anyhow::Result<()> {
    for path in std::env::args().skip(1) {
        let s = host_sim::model::scenario::Scenario::load(std::path::Path::new(&path))?;
        let r = host_sim::studies::ablation::no_dive::hover_half_turns(&s)?;
        let line: Vec<String> = r
            .iter()
            .map(|(l, a, t)| {
                format!(
                    "{l}: {a:.2} m / {}",
                    t.map_or("-".into(), |t| format!("{t:.1} s"))
                )
            })
            .collect();
        println!("{path}\n  {}", line.join("\n  "));
    }
    Ok(())
}
