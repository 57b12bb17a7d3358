//! TEMP stub
#![allow(missing_docs)]
#[derive(Debug, thiserror::Error)]
#[error("stub")]
pub struct OutputError;
