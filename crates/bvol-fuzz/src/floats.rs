//! Numbers from fuzz bytes, biased towards the values that break geometry:
//! the edges of f32, the limits bvol sets, zero and its neighbours, and
//! ordinary sizes (so that most inputs still reach the code past the checks).

use arbitrary::{Result, Unstructured};
use bvol::glam::{Quat, Vec3, Vec4};
use bvol::{MAX_COORDINATE, ROTATION_LENGTH_SQUARED};

/// Values at the edges of what bvol takes or f32 holds.
const EDGES: &[f32] = &[
    0.0,
    -0.0,
    1.0,
    -1.0,
    f32::MIN_POSITIVE,
    1e-45,
    1e-44,
    1e-20,
    1e-9,
    1e9,
    MAX_COORDINATE,
    -MAX_COORDINATE,
    1.0000001e18,
    1e20,
    f32::MAX,
    f32::MIN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::NAN,
    f32::EPSILON,
    1.0 + f32::EPSILON,
];

/// A float: an edge value or any bit pattern (one in eight), a small whole
/// number or fraction, or a modest number at a scale from 1e-8 to 1e8 (one
/// in sixteen from 1e-45 to 1e38).
pub fn float(u: &mut Unstructured) -> Result<f32> {
    Ok(match u.int_in_range(0u8..=15)? {
        0 => *u.choose(EDGES)?,
        1 => f32::from_bits(u.arbitrary()?),
        2..=5 => u.int_in_range(-8i8..=8)? as f32,
        6..=9 => u.int_in_range(-1000i16..=1000)? as f32 / 64.0,
        k => {
            let exponents = if k == 15 { -45..=38 } else { -8..=8 };
            let mantissa = u.int_in_range(-1000i16..=1000)? as f32 / 100.0;
            mantissa * 10f32.powi(u.int_in_range(exponents)?)
        }
    })
}

/// Usually a tame value (`tame`), one time in `odds` any [`float`]: so that
/// an input of many numbers is not nearly always refused for one of them.
pub fn rarely_wild<T>(
    u: &mut Unstructured,
    odds: u8,
    wild: impl FnOnce(&mut Unstructured) -> Result<T>,
    tame: impl FnOnce(&mut Unstructured) -> Result<T>,
) -> Result<T> {
    if u.ratio(1u8, odds)? { wild(u) } else { tame(u) }
}

/// A size: mostly within 1e-3..=4e3, one time in sixteen any float.
pub fn size(u: &mut Unstructured) -> Result<f32> {
    rarely_wild(u, 16, float, |u| {
        Ok(u.int_in_range(1u16..=4000)? as f32 / 1000.0 * 10f32.powi(u.int_in_range(-3i32..=3)?))
    })
}

/// A point: three floats.
pub fn vec3(u: &mut Unstructured) -> Result<Vec3> {
    Ok(Vec3::new(float(u)?, float(u)?, float(u)?))
}

/// A position within 4 of the origin, one time in sixteen anywhere.
pub fn position(u: &mut Unstructured) -> Result<Vec3> {
    rarely_wild(u, 16, vec3, |u| {
        let small = |u: &mut Unstructured| Ok(u.int_in_range(-400i16..=400)? as f32 / 100.0);
        Ok(Vec3::new(small(u)?, small(u)?, small(u)?))
    })
}

/// A rotation: usually unit, sometimes of any length, or not finite (a world
/// takes lengths squared within [`ROTATION_LENGTH_SQUARED`]).
pub fn rotation(u: &mut Unstructured) -> Result<Quat> {
    let q = Quat::from_xyzw(float(u)?, float(u)?, float(u)?, float(u)?);
    Ok(match u.int_in_range(0u8..=3)? {
        0 => q,
        1 => {
            let length = *u.choose(&[
                ROTATION_LENGTH_SQUARED.start().sqrt(),
                ROTATION_LENGTH_SQUARED.end().sqrt(),
                0.5,
                3.0,
            ])?;
            normalized(q).map_or(q, |n| n * length)
        }
        _ => normalized(q).unwrap_or(Quat::IDENTITY),
    })
}

fn normalized(q: Quat) -> Option<Quat> {
    Vec4::from(q).try_normalize().map(Quat::from_vec4)
}
