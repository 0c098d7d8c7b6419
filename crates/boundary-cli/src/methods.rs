//! `boundary methods`: the registered methods with their parameters and defaults.

use crate::error::CliError;
use crate::output::outln;
use boundary::{detector_with_params, methods, summary};
use clap::Args;
use serde_json::json;

#[derive(Debug, Args)]
pub(crate) struct MethodsArgs {
    /// Print a JSON array instead of the text list.
    #[arg(long)]
    json: bool,
}

pub(crate) fn list_methods(args: MethodsArgs) -> Result<(), CliError> {
    let mut entries = Vec::new();
    for name in methods() {
        let detector = detector_with_params::<&str, &str>(name, &[])?;
        entries.push((name, detector));
    }
    if args.json {
        let list: Vec<_> = entries
            .iter()
            .map(|(name, d)| {
                json!({
                    "name": name,
                    "summary": summary(name),
                    "certified": d.certified(),
                    "params": d.describe().0.iter().map(|p| json!({
                        "name": p.name, "default": p.default, "description": p.description,
                    })).collect::<Vec<_>>(),
                })
            })
            .collect();
        outln!("{}", serde_json::Value::Array(list))?;
        return Ok(());
    }
    for (name, d) in &entries {
        let tag = if d.certified() { " [certified]" } else { "" };
        outln!("{name}{tag}: {}", summary(name).unwrap_or(""))?;
        let params = d.describe();
        if params.0.is_empty() {
            outln!("    (no parameters)")?;
        }
        for p in &params.0 {
            outln!("    --set {}={}  {}", p.name, p.default, p.description)?;
        }
    }
    Ok(())
}
