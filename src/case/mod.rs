//! Case files: schema, loading with overrides, validation.

mod load;
mod schema;
mod validate;

pub use load::{apply_overrides, load_case, load_text, parse_case, CaseError, LoadedCase};
pub use schema::*;
pub use validate::{
    estimated_particles, initial_memory, validate, INITIAL_MEMORY_MAX, SAMPLES_MAX, STEPS_MAX,
    STEPS_PER_ROTATION_MIN,
};
