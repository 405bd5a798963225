//! Values the commands take, parsed at the edge into types (clap value parsers through
//! `FromStr`), so a bad one is clap's error naming the option: moves, turns, BRDF edits, image
//! sizes, colours and number pairs.

use glam::Vec3;
use vcut_scene::Material;
use vcut_scene::limits::Limit;
use vcut_shade::brdf::{SpecError, parse_spec};

/// An image's side (`--width`, `--height`, each side of `--size`).
pub const SIDE: Limit = Limit::within(1.0, Size::MAX_SIDE as f64, "pixels");
/// `--exposure`: the factor before tone mapping.
pub const EXPOSURE: Limit = Limit::above(0.0, "");
/// `--env-rotation`: the map's turn about the vertical, as a scene's `rotation_deg`.
pub const ENV_ROTATION: Limit = vcut_scene::check::ROTATION;
/// `--live-move-ms`: the viewer's time for a drag step.
pub const LIVE_MOVE_MS: Limit = Limit::at_least(0.0, "ms");

/// `NAME=DX,DY,DZ`: move object NAME to this translation from its rest position (finite; one
/// its mesh cannot take in f32 is refused when the move is made, naming the spacing f32 keeps
/// there: `vcut_shade::FrameError::Placement`).
#[derive(Debug, Clone, PartialEq)]
pub struct Move {
    /// The object's name.
    pub object: String,
    /// Its translation from rest.
    pub translation: Vec3,
}

impl std::str::FromStr for Move {
    type Err = String;

    fn from_str(s: &str) -> Result<Move, String> {
        let (name, v) = s.split_once('=').ok_or_else(|| format!("{s:?}: expected NAME=DX,DY,DZ"))?;
        let [dx, dy, dz] = numbers::<3>(v).map_err(|e| format!("{s:?}: {e}"))?;
        let t = Vec3::new(dx, dy, dz);
        if name.is_empty() {
            return Err(format!("{s:?}: expected an object's name before `=`"));
        }
        Ok(Move { object: name.into(), translation: t })
    }
}

impl std::fmt::Display for Move {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let t = self.translation;
        write!(f, "{}={},{},{}", self.object, t.x, t.y, t.z)
    }
}

/// `NAME=DEGREES`: turn object NAME about +Y (+X toward −Z) by this many degrees from its rest
/// orientation (finite; `vcut_shade::Frame::turn`, which refuses a file without a symmetric
/// direction set, naming `turn_steps`).
#[derive(Debug, Clone, PartialEq)]
pub struct TurnTo {
    /// The object's name.
    pub object: String,
    /// Its yaw from rest (degrees).
    pub degrees: f32,
}

impl std::str::FromStr for TurnTo {
    type Err = String;

    fn from_str(s: &str) -> Result<TurnTo, String> {
        let (name, v) = s.split_once('=').ok_or_else(|| format!("{s:?}: expected NAME=DEGREES"))?;
        let [degrees] = numbers::<1>(v).map_err(|e| format!("{s:?}: {e}"))?;
        if name.is_empty() {
            return Err(format!("{s:?}: expected an object's name before `=`"));
        }
        Ok(TurnTo { object: name.into(), degrees })
    }
}

impl std::fmt::Display for TurnTo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}={}", self.object, self.degrees)
    }
}

/// `NAME=MODEL[:KEY=VALUE,...]`: a BRDF edit of object NAME (`vcut_shade::brdf::parse_spec`).
/// The spec is checked when parsed (against a default material), and applied to the object's
/// own material later.
#[derive(Debug, Clone, PartialEq)]
pub struct BrdfEdit {
    /// The object's name.
    pub object: String,
    /// The edit, as `parse_spec` reads it.
    pub spec: String,
}

impl BrdfEdit {
    /// `base` with this edit applied.
    pub fn apply(&self, base: Material) -> Result<Material, SpecError> {
        parse_spec(base, &self.spec)
    }
}

impl std::str::FromStr for BrdfEdit {
    type Err = String;

    fn from_str(s: &str) -> Result<BrdfEdit, String> {
        let (name, spec) = s.split_once('=').ok_or_else(|| format!("{s:?}: expected NAME=MODEL[:KEY=VALUE,...]"))?;
        if name.is_empty() {
            return Err(format!("{s:?}: expected an object's name before `=`"));
        }
        parse_spec(Material::default(), spec).map_err(|e| format!("{s:?}: {e}"))?;
        Ok(BrdfEdit { object: name.into(), spec: spec.into() })
    }
}

impl std::fmt::Display for BrdfEdit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}={}", self.object, self.spec)
    }
}

/// `WIDTHxHEIGHT`: an image size, each side 1 to [`Size::MAX_SIDE`] pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Size {
    /// Pixels across.
    pub width: u32,
    /// Pixels down.
    pub height: u32,
}

impl Size {
    /// The largest side an image takes.
    pub const MAX_SIDE: u32 = 16_384;

    /// `width` × `height`, each side checked ([`SIDE`]).
    pub fn new(width: u32, height: u32) -> Result<Size, String> {
        for (side, what) in [(width, "width"), (height, "height")] {
            SIDE.check(f64::from(side)).map_err(|reason| format!("{what} {side}: {reason}"))?;
        }
        Ok(Size { width, height })
    }
}

impl std::str::FromStr for Size {
    type Err = String;

    fn from_str(s: &str) -> Result<Size, String> {
        let (w, h) = s.split_once('x').ok_or_else(|| format!("{s:?}: expected WIDTHxHEIGHT"))?;
        Ok(Size {
            width: side(w).map_err(|e| format!("{s:?}: width {e}"))?,
            height: side(h).map_err(|e| format!("{s:?}: height {e}"))?,
        })
    }
}

impl std::fmt::Display for Size {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}x{}", self.width, self.height)
    }
}

/// An image side in pixels ([`SIDE`]: `--width`, `--height`).
pub fn side(s: &str) -> Result<u32, String> {
    SIDE.parse_whole(s).map(|n| n as u32)
}

/// `R,G,B` (or one value for all three): finite and ≥ 0, such as a reflectance or a coefficient.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rgb(pub Vec3);

impl std::str::FromStr for Rgb {
    type Err = String;

    fn from_str(s: &str) -> Result<Rgb, String> {
        let v = list(s)?;
        match v.as_slice() {
            [r, g, b] if v.iter().all(|x| *x >= 0.0) => Ok(Rgb(Vec3::new(*r, *g, *b))),
            [x] if *x >= 0.0 => Ok(Rgb(Vec3::splat(*x))),
            _ => Err(format!("{s:?}: expected three non-negative numbers R,G,B (or one for all three)")),
        }
    }
}

/// `A,B`: two finite numbers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pair(pub f32, pub f32);

impl std::str::FromStr for Pair {
    type Err = String;

    fn from_str(s: &str) -> Result<Pair, String> {
        let [a, b] = numbers::<2>(s).map_err(|e| format!("{s:?}: {e}"))?;
        Ok(Pair(a, b))
    }
}

/// Comma-separated finite numbers.
fn list(s: &str) -> Result<Vec<f32>, String> {
    s.split(',')
        .map(|x| {
            let v: f32 = x.trim().parse().map_err(|_| format!("{s:?}: {x:?} is not a number"))?;
            if v.is_finite() { Ok(v) } else { Err(format!("{s:?}: {x:?} is not finite")) }
        })
        .collect()
}

/// Exactly `N` comma-separated finite numbers.
fn numbers<const N: usize>(s: &str) -> Result<[f32; N], String> {
    let v = list(s)?;
    v.try_into().map_err(|v: Vec<f32>| format!("expected {N} comma-separated numbers, got {}", v.len()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_parse_print_back_and_refuse_what_is_wrong() {
        let m: Move = "teapot=0.6,0,-0.4".parse().unwrap();
        assert_eq!((m.object.as_str(), m.translation), ("teapot", Vec3::new(0.6, 0.0, -0.4)));
        assert_eq!(m.to_string().parse::<Move>().unwrap(), m);
        for bad in ["teapot", "teapot=1,2", "teapot=nan,0,0", "teapot=inf,0,0", "teapot=1e39,0,0", "=1,2,3", "t=1,,3"] {
            assert!(bad.parse::<Move>().is_err(), "{bad}");
        }
        let t: TurnTo = "teapot=-37.5".parse().unwrap();
        assert_eq!((t.object.as_str(), t.degrees), ("teapot", -37.5));
        assert_eq!(t.to_string().parse::<TurnTo>().unwrap(), t);
        for bad in ["teapot", "teapot=", "teapot=nan", "teapot=inf", "teapot=1,2", "=30", "teapot=1e39"] {
            assert!(bad.parse::<TurnTo>().is_err(), "{bad}");
        }
        let b: BrdfEdit = "teapot=blinn-phong:alpha=70".parse().unwrap();
        assert_eq!(b.apply(Material::default()).unwrap().exponent, 70.0);
        for bad in ["teapot", "teapot=plastic", "teapot=phong:alpha=nan", "teapot=phong:kd=1/2"] {
            assert!(bad.parse::<BrdfEdit>().is_err(), "{bad}");
        }
        assert_eq!("960x720".parse::<Size>().unwrap(), Size { width: 960, height: 720 });
        for bad in ["960", "0x720", "960x100000", "axb", "-1x2"] {
            assert!(bad.parse::<Size>().is_err(), "{bad}");
        }
        assert!(side("0").is_err() && side("100000000").is_err() && side("640").is_ok());
        assert_eq!(side("0").unwrap_err(), "\"0\": must be a whole number in [1, 16384] pixels");
        assert_eq!("0.5".parse::<Rgb>().unwrap(), Rgb(Vec3::splat(0.5)));
        assert!("1,2".parse::<Rgb>().is_err() && "-1,0,0".parse::<Rgb>().is_err());
        assert_eq!("0.1,0.3".parse::<Pair>().unwrap(), Pair(0.1, 0.3));
        assert!("0.1,inf".parse::<Pair>().is_err());
    }
}
