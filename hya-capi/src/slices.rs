//! From C's pointer and length to checked Rust slices: null, a wrong length and non-finite
//! values are failures named after the argument, found before anything is read past the length.

use crate::status::Failure;

/// `n` values at `ptr`, which must be `expected` long and finite.
///
/// # Safety
/// `ptr` is null or valid for reading `n` doubles.
pub(crate) unsafe fn input<'a>(
    name: &'static str,
    ptr: *const f64,
    n: usize,
    expected: usize,
) -> Result<&'a [f64], Failure> {
    let values = unsafe { raw(name, ptr, n, expected) }?;
    finite(name, values)?;
    Ok(values)
}

/// Like [`input`], but null means "not given".
///
/// # Safety
/// As [`input`].
pub(crate) unsafe fn optional_input<'a>(
    name: &'static str,
    ptr: *const f64,
    n: usize,
    expected: usize,
) -> Result<Option<&'a [f64]>, Failure> {
    if ptr.is_null() {
        Ok(None)
    } else {
        // SAFETY: the caller's contract.
        unsafe { input(name, ptr, n, expected) }.map(Some)
    }
}

/// `n` writable values at `ptr`, which must be `expected` long and lie apart from every one of
/// `inputs` (a caller's in-place call would otherwise read what it writes, and a Rust `&mut`
/// over a `&` is undefined behaviour).
///
/// # Safety
/// `ptr` is null or valid for writing `n` doubles.
pub(crate) unsafe fn output<'a>(
    name: &'static str,
    ptr: *mut f64,
    n: usize,
    expected: usize,
    inputs: &[&[f64]],
) -> Result<&'a mut [f64], Failure> {
    // SAFETY: the caller's contract.
    let [out] = unsafe { outputs([(name, ptr)], n, expected, inputs) }?;
    Ok(out)
}

/// A controller's torque output `tau` ([`output`]), apart from its state `(q, q̇)`, its reference
/// and `d̂`.
///
/// # Safety
/// `tau` is null or valid for writing `n` doubles.
pub(crate) unsafe fn command_output<'a>(
    tau: *mut f64,
    (n, dof): (usize, usize),
    state: [&[f64]; 2],
    reference: [&[f64]; 3],
    d_hat: Option<&[f64]>,
) -> Result<&'a mut [f64], Failure> {
    let inputs = [state[0], state[1], reference[0], reference[1], reference[2], d_hat.unwrap_or(&[])];
    // SAFETY: the caller's contract.
    unsafe { output("tau", tau, n, dof, &inputs) }
}

/// The bytes `[start, end)` that `n` values at `p` occupy; an end past the address space is
/// taken as its top (no such array exists, and the comparison stays correct).
pub(crate) fn span<T>(p: *const T, n: usize) -> (usize, usize) {
    let start = p as usize;
    (start, start.saturating_add(n.saturating_mul(core::mem::size_of::<T>())))
}

/// Whether two spans of bytes ([`span`]) share one: an empty span shares none, two arrays that
/// only touch share none.
pub(crate) fn overlap((start, end): (usize, usize), (other_start, other_end): (usize, usize)) -> bool {
    start < end && other_start < other_end && start < other_end && other_start < end
}

/// [`Failure::Aliased`] if the output `name` (`len` doubles at its pointer) overlaps an input.
pub(crate) fn apart(name: &'static str, (ptr, len): (*mut f64, usize), inputs: &[&[f64]]) -> Result<(), Failure> {
    let output = span(ptr.cast_const(), len);
    match inputs.iter().any(|input| overlap(output, span(input.as_ptr(), input.len()))) {
        true => Err(Failure::Aliased(name)),
        false => Ok(()),
    }
}

/// Several outputs of `n` values each, which must be `expected` long and lie apart from each
/// other and from every one of `inputs`: checked (null, length, overlaps) before any is made a
/// slice.
///
/// # Safety
/// Each pointer is null or valid for writing `n` doubles.
pub(crate) unsafe fn outputs<'a, const K: usize>(
    arguments: [(&'static str, *mut f64); K],
    n: usize,
    expected: usize,
    inputs: &[&[f64]],
) -> Result<[&'a mut [f64]; K], Failure> {
    for (name, ptr) in arguments {
        check(name, ptr.is_null(), n, expected)?;
        apart(name, (ptr, n), inputs)?;
    }
    for (k, (name, ptr)) in arguments.iter().enumerate() {
        if arguments[..k].iter().any(|(_, other)| overlap(span(ptr.cast_const(), n), span(other.cast_const(), n))) {
            return Err(Failure::Aliased(name));
        }
    }
    // SAFETY: non-null, `n` long by the caller's contract, apart from each other and from
    // every input.
    Ok(arguments.map(|(_, ptr)| unsafe { core::slice::from_raw_parts_mut(ptr, n) }))
}

/// `count` rows of `width` writable values at `ptr` ([`output`] of `count × width`).
///
/// # Safety
/// `ptr` is null or valid for writing `count × width` doubles.
pub(crate) unsafe fn output_rows<'a>(
    name: &'static str,
    ptr: *mut f64,
    (count, width): (usize, usize),
    inputs: &[&[f64]],
) -> Result<&'a mut [f64], Failure> {
    let len = rows_length(name, count, width)?;
    // SAFETY: the caller's contract.
    unsafe { output(name, ptr, len, len, inputs) }
}

/// `count × width`, or a failure if that many doubles cannot be addressed.
pub(crate) fn rows_length(name: &'static str, count: usize, width: usize) -> Result<usize, Failure> {
    count
        .checked_mul(width)
        .filter(|&len| len <= isize::MAX as usize / core::mem::size_of::<f64>())
        .ok_or(Failure::TooManyRows { name, count, width })
}

/// `Err` at the first non-finite value.
fn finite(name: &'static str, values: &[f64]) -> Result<(), Failure> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(Failure::NonFinite { name, index, value: values[index] }),
        None => Ok(()),
    }
}

unsafe fn raw<'a>(name: &'static str, ptr: *const f64, n: usize, expected: usize) -> Result<&'a [f64], Failure> {
    check(name, ptr.is_null(), n, expected)?;
    // SAFETY: non-null, and the caller's contract gives `n` readable doubles.
    Ok(unsafe { core::slice::from_raw_parts(ptr, n) })
}

fn check(name: &'static str, null: bool, n: usize, expected: usize) -> Result<(), Failure> {
    if null {
        Err(Failure::Null(name))
    } else if n != expected {
        Err(Failure::Length { name, got: n, expected })
    } else {
        Ok(())
    }
}

/// `count` rows of `n` values at `ptr`, one after another: `n` must be `dof`, and every value
/// finite (a failure names the row and the joint).
///
/// # Safety
/// `ptr` is null or valid for reading `count × n` doubles.
pub(crate) unsafe fn input_rows<'a>(
    name: &'static str,
    ptr: *const f64,
    (count, n): (usize, usize),
    dof: usize,
) -> Result<&'a [f64], Failure> {
    if n != dof {
        return Err(Failure::RowWidth { name, got: n, expected: dof });
    }
    let len = rows_length(name, count, n)?;
    // SAFETY: the caller's contract.
    unsafe { input(name, ptr, len, len) }.map_err(|failure| match failure {
        Failure::NonFinite { name, index, value } => {
            Failure::NonFiniteInRow { name, row: index / n, index: index % n, value }
        }
        other => other,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_overlap_when_they_share_a_byte_and_not_when_they_touch() {
        let values = [0.0f64; 8];
        let at = |k: usize, n: usize| span(values[k..].as_ptr(), n);
        assert!(overlap(at(0, 4), at(3, 2)), "partial");
        assert!(overlap(at(0, 8), at(2, 2)) && overlap(at(2, 2), at(0, 8)), "one inside the other");
        assert!(overlap(at(1, 3), at(1, 3)), "the same");
        assert!(!overlap(at(0, 4), at(4, 4)) && !overlap(at(4, 4), at(0, 4)), "touching");
        assert!(!overlap(at(0, 0), at(0, 8)) && !overlap(at(0, 8), at(3, 0)), "empty");
        // A length no array has reaches the top of the address space instead of wrapping.
        assert_eq!(span(values.as_ptr(), usize::MAX).1, usize::MAX);
        assert!(overlap(span(values.as_ptr(), usize::MAX), at(7, 1)));
    }
}
