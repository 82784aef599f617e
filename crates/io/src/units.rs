//! Length units of mesh files; flatcut works in millimetres.

use std::fmt;
use std::str::FromStr;

/// The length unit the coordinates of a file are in.
///
/// Readers multiply positions by [`Units::factor_to_mm`] so that meshes inside flatcut are
/// always in millimetres; writers divide by it. `Mm` leaves coordinates bit-exact.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Deserialize, serde::Serialize,
)]
#[serde(rename_all = "lowercase")]
pub enum Units {
    /// Millimetres (factor 1).
    #[default]
    Mm,
    /// Centimetres (factor 10).
    Cm,
    /// Decimetres (factor 100; MakeHuman exports).
    Dm,
    /// Metres (factor 1000; glTF's unit by specification).
    M,
    /// Inches (factor 25.4).
    #[serde(alias = "inch")]
    In,
}

impl Units {
    /// The units a format's coordinates are in when nobody says otherwise: metres for glTF
    /// and GLB (fixed by the glTF specification), millimetres for OBJ, PLY and STL (which
    /// carry no units; scans and CAD exports are mostly millimetres).
    pub fn default_for(format: crate::Format) -> Units {
        match format {
            crate::Format::Gltf | crate::Format::Glb => Units::M,
            crate::Format::Obj | crate::Format::Ply | crate::Format::Stl => Units::Mm,
        }
    }

    /// How many millimetres one unit is.
    pub fn factor_to_mm(self) -> f64 {
        match self {
            Units::Mm => 1.0,
            Units::Cm => 10.0,
            Units::Dm => 100.0,
            Units::M => 1000.0,
            Units::In => 25.4,
        }
    }

    /// The short name ("mm", "cm", "dm", "m", "in").
    pub fn name(self) -> &'static str {
        match self {
            Units::Mm => "mm",
            Units::Cm => "cm",
            Units::Dm => "dm",
            Units::M => "m",
            Units::In => "in",
        }
    }
}

impl fmt::Display for Units {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The error of parsing a [`Units`] name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown length unit '{0}'; use one of mm, cm, dm, m, in")]
pub struct ParseUnitsError(pub String);

impl FromStr for Units {
    type Err = ParseUnitsError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "mm" => Ok(Units::Mm),
            "cm" => Ok(Units::Cm),
            "dm" => Ok(Units::Dm),
            "m" => Ok(Units::M),
            "in" | "inch" | "inches" => Ok(Units::In),
            _ => Err(ParseUnitsError(s.to_string())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_and_factor() {
        for (s, u, f) in [
            ("mm", Units::Mm, 1.0),
            ("CM", Units::Cm, 10.0),
            ("dm", Units::Dm, 100.0),
            ("m", Units::M, 1000.0),
            ("in", Units::In, 25.4),
            ("inch", Units::In, 25.4),
        ] {
            let parsed: Units = s.parse().unwrap();
            assert_eq!(parsed, u);
            assert_eq!(parsed.factor_to_mm(), f);
            assert_eq!(parsed.name().parse::<Units>().unwrap(), u);
        }
        assert!("ft".parse::<Units>().is_err());
    }
}
