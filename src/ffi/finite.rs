//! Answers a double can hold. A query whose answer is not representable (shapes placed within
//! their size of the largest double, so that a witness or contact point, x* or α* passes it)
//! returns `DCOL_ERROR_INVALID_POSE` naming the position, and writes nothing: no infinity or
//! NaN is written on `DCOL_OK` (or with `DCOL_ERROR_NOT_CONVERGED`).

use super::boundary::Failure;
use crate::math::Vec3;
use crate::query::Proximity;

/// `Ok` when `finite` (every number of the answer about to be written is finite), otherwise
/// the `DCOL_ERROR_INVALID_POSE` failure naming the largest coordinate of the origins `r1`,
/// `r2` (that of [`super::boundary::representable`]).
#[inline]
pub(crate) fn representable(finite: bool, r1: &Vec3, r2: &Vec3) -> Result<(), Failure> {
    if finite {
        return Ok(());
    }
    Err(Failure::api(crate::query::not_representable(r1, r2)))
}

/// The numbers of a proximity result: α*, x* and the contact points.
#[inline]
pub(crate) fn proximity_numbers(p: &Proximity) -> [f64; 10] {
    let (x, c1, c2) = (&p.point, &p.contact1, &p.contact2);
    [p.alpha, x.x, x.y, x.z, c1.x, c1.y, c1.z, c2.x, c2.y, c2.z]
}
