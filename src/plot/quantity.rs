//! What `tumbler plot field` can show (`--quantity`) and where (`--plane`).

use crate::inspect::InspectError;

/// Every accepted `--quantity`, for messages and `--help`.
pub const QUANTITIES: &str = "number_density:S, volume_fraction:S, axial_flux:S (S a species \
index or name), u, v, w, ud, vd, wd, u_rms, v_rms, w_rms, rms, depth, boundary, surface";

/// A per-species field of `/fields`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpeciesField {
    /// `/fields/number_density`.
    NumberDensity,
    /// `/fields/volume_fraction`.
    VolumeFraction,
    /// `/fields/axial_flux`.
    AxialFlux,
}

/// A per-column (`F x X x ZF`) field of `/fields`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColumnField {
    /// `/fields/depth`.
    Depth,
    /// `/fields/boundary`.
    Boundary,
    /// `/fields/surface`.
    Surface,
}

/// A quantity of `/fields` to draw.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Quantity {
    /// A species' field (index `species`).
    Species {
        /// Which field.
        field: SpeciesField,
        /// Species index.
        species: usize,
    },
    /// A component (0, 1, 2 = u, v, w) of `/fields/velocity` or, `drum`, of
    /// `/fields/velocity_drum`.
    Velocity {
        /// Drum frame rather than lab frame.
        drum: bool,
        /// Component index.
        component: usize,
    },
    /// A component (0..3 = u_rms, v_rms, w_rms, rms) of `/fields/rms`.
    Rms {
        /// Component index.
        component: usize,
    },
    /// A column field (one value per `(x, z)` column).
    Column(ColumnField),
}

impl Quantity {
    /// Parse `--quantity`; a species may be given by index or by one of `species` names.
    pub fn parse(text: &str, species: &[String]) -> Result<Self, InspectError> {
        let bad = || {
            InspectError::Invalid(format!(
                "unknown quantity '{text}' (--quantity): expected one of {QUANTITIES}"
            ))
        };
        if let Some((name, s)) = text.split_once(':') {
            let field = match name {
                "number_density" => SpeciesField::NumberDensity,
                "volume_fraction" => SpeciesField::VolumeFraction,
                "axial_flux" => SpeciesField::AxialFlux,
                _ => return Err(bad()),
            };
            let species = resolve_species(s, species).ok_or_else(|| {
                let known: Vec<String> = species
                    .iter()
                    .enumerate()
                    .map(|(i, n)| format!("{i} ({n})"))
                    .collect();
                InspectError::Invalid(format!(
                    "unknown species '{s}' in --quantity {text}: give an index{}",
                    if known.is_empty() {
                        String::new()
                    } else {
                        format!(" or a name; the file's species are {}", known.join(", "))
                    }
                ))
            })?;
            return Ok(Quantity::Species { field, species });
        }
        let q = match text {
            "u" | "v" | "w" => Quantity::Velocity {
                drum: false,
                component: component(&text[..1]),
            },
            "ud" | "vd" | "wd" => Quantity::Velocity {
                drum: true,
                component: component(&text[..1]),
            },
            "u_rms" | "v_rms" | "w_rms" => Quantity::Rms {
                component: component(&text[..1]),
            },
            "rms" => Quantity::Rms { component: 3 },
            "depth" => Quantity::Column(ColumnField::Depth),
            "boundary" => Quantity::Column(ColumnField::Boundary),
            "surface" => Quantity::Column(ColumnField::Surface),
            "number_density" | "volume_fraction" | "axial_flux" => {
                return Err(InspectError::Invalid(format!(
                    "--quantity {text} needs a species: {text}:S, S a species index or name"
                )))
            }
            _ => return Err(bad()),
        };
        Ok(q)
    }

    /// The dataset the quantity is read from.
    pub fn dataset(&self) -> &'static str {
        match self {
            Quantity::Species { field, .. } => match field {
                SpeciesField::NumberDensity => "fields/number_density",
                SpeciesField::VolumeFraction => "fields/volume_fraction",
                SpeciesField::AxialFlux => "fields/axial_flux",
            },
            Quantity::Velocity { drum: false, .. } => "fields/velocity",
            Quantity::Velocity { drum: true, .. } => "fields/velocity_drum",
            Quantity::Rms { .. } => "fields/rms",
            Quantity::Column(c) => match c {
                ColumnField::Depth => "fields/depth",
                ColumnField::Boundary => "fields/boundary",
                ColumnField::Surface => "fields/surface",
            },
        }
    }

    /// Index along the dataset's second axis (species or component); 0 for column fields.
    pub fn channel(&self) -> usize {
        match *self {
            Quantity::Species { species, .. } => species,
            Quantity::Velocity { component, .. } | Quantity::Rms { component } => component,
            Quantity::Column(_) => 0,
        }
    }

    /// Whether the quantity takes both signs (drawn with a diverging colour map).
    pub fn signed(&self) -> bool {
        matches!(
            self,
            Quantity::Velocity { .. }
                | Quantity::Species {
                    field: SpeciesField::AxialFlux,
                    ..
                }
        )
    }

    /// Whether the default plane is the free-surface layer (velocities), not `z` = 0.
    pub fn surface_by_default(&self) -> bool {
        matches!(self, Quantity::Velocity { .. } | Quantity::Rms { .. })
    }

    /// Whether the quantity is one value per `(x, z)` column (`F x X x ZF`).
    pub fn is_column(&self) -> bool {
        matches!(self, Quantity::Column(_))
    }

    /// What the quantity is, in words, for titles and colour bars (`axial velocity w,
    /// drum frame`, `volume fraction of big`): no internal keys.
    pub fn title(&self, species: &[String]) -> String {
        let uvw = [
            "streamwise velocity u",
            "surface-normal velocity v",
            "axial velocity w",
        ];
        let rms = ["u_rms", "v_rms", "w_rms"];
        let of = |s: usize| match species.get(s) {
            Some(n) => n.clone(),
            None => format!("species {s}"),
        };
        match *self {
            Quantity::Species { field, species: s } => match field {
                SpeciesField::NumberDensity => format!("number density of {}", of(s)),
                SpeciesField::VolumeFraction => format!("volume fraction of {}", of(s)),
                SpeciesField::AxialFlux => format!("axial particle flux of {}", of(s)),
            },
            Quantity::Velocity { drum, component } => format!(
                "{}, {} frame",
                uvw[component],
                if drum { "drum" } else { "lab" }
            ),
            Quantity::Rms { component: 3 } => "velocity fluctuation (rms, drum frame)".into(),
            Quantity::Rms { component } => {
                format!("velocity fluctuation {} (drum frame)", rms[component])
            }
            Quantity::Column(c) => match c {
                ColumnField::Depth => "flowing-layer depth".into(),
                ColumnField::Boundary => "height of the flowing-layer boundary".into(),
                ColumnField::Surface => "height of the free surface".into(),
            },
        }
    }

    /// Short name for file names (`w`, `volume_fraction:big`).
    pub fn name(&self, species: &[String]) -> String {
        let uvw = ["u", "v", "w", ""];
        match *self {
            Quantity::Species { species: s, .. } => {
                let field = self.dataset().trim_start_matches("fields/");
                match species.get(s) {
                    Some(n) => format!("{field}:{n}"),
                    None => format!("{field}:{s}"),
                }
            }
            Quantity::Velocity { drum, component } => {
                format!("{}{}", uvw[component], if drum { "d" } else { "" })
            }
            Quantity::Rms { component: 3 } => "rms".into(),
            Quantity::Rms { component } => format!("{}_rms", uvw[component]),
            Quantity::Column(_) => self.dataset().trim_start_matches("fields/").into(),
        }
    }
}

fn component(axis: &str) -> usize {
    match axis {
        "u" => 0,
        "v" => 1,
        _ => 2,
    }
}

/// A species index, or the index of the species named `s`.
fn resolve_species(s: &str, species: &[String]) -> Option<usize> {
    s.parse::<usize>()
        .ok()
        .or_else(|| species.iter().position(|n| n == s))
}

/// The cut through the `X x Y x ZF` bins that is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Plane {
    /// `x = V`: a `z`-`y` map.
    X(f64),
    /// `y = V`: a `z`-`x` map.
    Y(f64),
    /// `z = V`: an `x`-`y` map (the cross-section).
    Z(f64),
    /// The free-surface layer: a `z`-`x` map of the highest filled bin of each column.
    Surface,
}

impl Plane {
    /// Parse `--plane` (`y=V`, `x=V`, `z=V` or `surface`).
    pub fn parse(text: &str) -> Result<Self, InspectError> {
        let bad = |why: &str| {
            InspectError::Invalid(format!(
                "bad plane '{text}' (--plane): {why}; expected y=V, x=V, z=V or surface"
            ))
        };
        if text == "surface" {
            return Ok(Plane::Surface);
        }
        let Some((axis, value)) = text.split_once('=') else {
            return Err(bad("no '='"));
        };
        let v: f64 = value
            .trim()
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| bad(&format!("'{value}' is not a number")))?;
        match axis.trim() {
            "x" => Ok(Plane::X(v)),
            "y" => Ok(Plane::Y(v)),
            "z" => Ok(Plane::Z(v)),
            other => Err(bad(&format!("unknown axis '{other}'"))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_quantities_and_planes() {
        let names = vec!["small".to_string(), "big".to_string()];
        let q = Quantity::parse("volume_fraction:big", &names).unwrap();
        assert_eq!(q.channel(), 1);
        assert_eq!(q.name(&names), "volume_fraction:big");
        assert_eq!(q.title(&names), "volume fraction of big");
        let ud = Quantity::parse("ud", &names).unwrap();
        assert_eq!(ud.title(&names), "streamwise velocity u, drum frame");
        assert!(!ud.title(&names).contains("ud"));
        assert_eq!(
            Quantity::parse("wd", &names).unwrap().dataset(),
            "fields/velocity_drum"
        );
        assert_eq!(Quantity::parse("rms", &names).unwrap().channel(), 3);
        assert!(Quantity::parse("w", &names).unwrap().signed());
        assert!(Quantity::parse("speed", &names).is_err());
        assert!(Quantity::parse("axial_flux:medium", &names).is_err());
        assert_eq!(Plane::parse("z=0.5").unwrap(), Plane::Z(0.5));
        assert_eq!(Plane::parse("surface").unwrap(), Plane::Surface);
        assert!(Plane::parse("q=1").is_err());
        assert!(Plane::parse("y=abc").is_err());
    }
}
