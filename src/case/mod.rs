//! Case files: schema, loading with overrides, validation.

mod load;
mod schema;
mod validate;

pub use load::{apply_overrides, load_case, parse_case, CaseError, LoadedCase};
pub use schema::*;
pub use validate::validate;
