//! `linkdyn schema`: prints the JSON Schema of the model file (draft 4) on stdout, for TOML
//! editors to complete and check model files (docs/model_format.md, "Editor support").

use super::{EXIT_OUTPUT, Failure};
use clap::Args;
use std::io::Write;

/// Arguments of `schema` (none: the schema goes to stdout).
#[derive(Debug, Args)]
pub struct SchemaArgs {}

/// Runs `schema`.
pub fn run(_: &SchemaArgs) -> Result<(), Failure> {
    let text =
        serde_json::to_string_pretty(&linkdyn::model::json_schema()).map_err(|e| Failure {
            code: EXIT_OUTPUT,
            message: format!("cannot write the schema: {e}"),
        })?;
    let mut out = std::io::stdout().lock();
    writeln!(out, "{text}")
        .and_then(|()| out.flush())
        .map_err(|e| Failure {
            code: EXIT_OUTPUT,
            message: format!("cannot write the schema to stdout: {e}"),
        })
}
