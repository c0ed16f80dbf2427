//! Status codes, the messages that explain them, and the guard that keeps panics on this side of
//! the boundary.

use core::fmt::{self, Write};
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::ffi::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::RwLock;

/// What a call did. `HYA_OK` is zero; every other value is a failure whose message is kept by
/// the handle (or, for creation and null handles, by `hya_last_error`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HyaStatus {
    /// Success; outputs were written.
    HyaOk = 0,
    /// A required pointer (handle, array, name, output) was null.
    HyaErrNull = 1,
    /// An array's length is not the model's joint count (or its square, for a mass matrix).
    HyaErrLength = 2,
    /// An input held NaN or an infinity; state is unchanged.
    HyaErrNonFinite = 3,
    /// A parameter is out of range (filter bandwidth, gain, sample time, ...), or a name is not
    /// a shipped arm or not a frame of the model, or a model has more joints than hya dispatches
    /// to, or an output overlaps an input or another output of the call.
    HyaErrInvalid = 4,
    /// A URDF or a friction file could not be read or is not valid.
    HyaErrModel = 5,
    /// A numerical failure: a singular mass matrix, an input beyond the filter's range.
    HyaErrNumeric = 6,
    /// A bug inside hya: a Rust panic, caught at the boundary.
    HyaErrPanic = 7,
    /// A handle that is not a live handle of the kind the call takes: one of another kind (an
    /// observer passed as a model), one already freed, or a pointer hya never made. Nothing was
    /// read through it.
    HyaErrHandle = 8,
}

/// Why a call failed, kept until it is written into a message.
#[derive(Debug)]
pub(crate) enum Failure {
    /// A null pointer for the argument named.
    Null(&'static str),
    /// An array of the wrong length.
    Length { name: &'static str, got: usize, expected: usize },
    /// More rows than memory can address.
    TooManyRows { name: &'static str, count: usize, width: usize },
    /// Rows of a batch argument whose width is not the model's joint count.
    RowWidth { name: &'static str, got: usize, expected: usize },
    /// A non-finite input value in row `row` of a batch argument.
    NonFiniteInRow { name: &'static str, row: usize, index: usize, value: f64 },
    /// A non-finite input value.
    NonFinite { name: &'static str, index: usize, value: f64 },
    /// A string argument that is not UTF-8.
    NotUtf8(&'static str),
    /// A name no shipped arm has.
    UnknownArm(String),
    /// A model with a joint count outside what hya dispatches to.
    JointCount { model: String, dof: usize },
    /// hya-core refused the call.
    Core(hya_core::Error),
    /// The URDF loader refused the file.
    Load(hya_urdf::LoadError),
    /// The run-time model refused the description.
    Model(hya_core::model::ModelError),
    /// The friction file (from `hya identify`) could not be read or was refused; the message
    /// names the file, the key and the value.
    Friction(String),
    /// An estimator stepped the other way than it was made for.
    Stepping { called: &'static str, needs: &'static str, made_by: &'static str, use_instead: &'static str },
    /// An output array that overlaps an input or another output of the same call.
    Aliased(&'static str),
    /// A pointer that is not a live handle of the kind expected.
    Handle { expected: &'static str, found: Option<&'static str> },
    /// A panic caught at the boundary.
    Panic(String),
    /// hya-core refused the state in row `row` (from 0) of a batch call.
    CoreInRow { row: usize, error: hya_core::Error },
}

impl Failure {
    /// The status code this failure is reported with.
    pub(crate) fn status(&self) -> HyaStatus {
        match self {
            Failure::Null(_) => HyaStatus::HyaErrNull,
            Failure::Length { .. } | Failure::TooManyRows { .. } | Failure::RowWidth { .. } => HyaStatus::HyaErrLength,
            Failure::NonFinite { .. } | Failure::NonFiniteInRow { .. } => HyaStatus::HyaErrNonFinite,
            Failure::NotUtf8(_)
            | Failure::UnknownArm(_)
            | Failure::JointCount { .. }
            | Failure::Stepping { .. }
            | Failure::Aliased(_) => HyaStatus::HyaErrInvalid,
            Failure::Core(e) => match e {
                hya_core::Error::NonFinite { .. } => HyaStatus::HyaErrNonFinite,
                hya_core::Error::SliceLength { .. }
                | hya_core::Error::BatchLength { .. }
                | hya_core::Error::PartialRow { .. } => HyaStatus::HyaErrLength,
                hya_core::Error::InvalidParameter { .. }
                | hya_core::Error::MissingMeasurement { .. }
                | hya_core::Error::Unsupported(_) => HyaStatus::HyaErrInvalid,
                _ => HyaStatus::HyaErrNumeric,
            },
            // A frame the model lacks is a bad argument, not a bad model.
            Failure::Model(hya_core::model::ModelError::UnknownFrame { .. }) => HyaStatus::HyaErrInvalid,
            Failure::Load(_) | Failure::Model(_) | Failure::Friction(_) => HyaStatus::HyaErrModel,
            Failure::Handle { .. } => HyaStatus::HyaErrHandle,
            Failure::Panic(_) => HyaStatus::HyaErrPanic,
            Failure::CoreInRow { error, .. } => Failure::Core(*error).status(),
        }
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::Null(name) => write!(f, "`{name}` is a null pointer"),
            Failure::Length { name, got, expected } => {
                write!(f, "`{name}` has length {got}; the model needs {expected}")
            }
            Failure::TooManyRows { name, count, width } => {
                write!(f, "`{name}`: {count} rows of {width} doubles are more than memory can address")
            }
            Failure::RowWidth { name, got, expected } => {
                write!(f, "`{name}` has rows of {got}; the model has {expected} joints")
            }
            Failure::NonFiniteInRow { name, row, index, value } => {
                write!(f, "row {row}: non-finite {name}[{index}] = {value}")
            }
            Failure::NonFinite { name, index, value } => write!(f, "non-finite {name}[{index}] = {value}"),
            Failure::NotUtf8(name) => write!(f, "`{name}` is not UTF-8"),
            Failure::UnknownArm(name) => {
                write!(f, "no shipped arm is called `{name}`; the shipped arms are")?;
                for (i, robot) in hya_robots::ROBOTS.iter().enumerate() {
                    write!(f, "{} {}", if i == 0 { "" } else { "," }, robot.name)?;
                }
                Ok(())
            }
            Failure::JointCount { model, dof } => {
                write!(f, "{model} has {dof} joints; hya handles 1 to {}", hya_core::dispatch::MAX_JOINTS)
            }
            Failure::Core(e) => write!(f, "{e}"),
            Failure::Load(e) => write!(f, "{e}"),
            Failure::Model(e) => write!(f, "{e}"),
            Failure::Friction(e) => write!(f, "friction: {e}"),
            Failure::Aliased(names) => {
                write!(f, "{names} overlaps another array of the call: outputs must be distinct from inputs and from each other")
            }
            Failure::Stepping { called, needs, made_by, use_instead } => write!(
                f,
                "{called} needs an estimator made by {needs}; this one was made by {made_by} and is stepped with {use_instead}"
            ),
            Failure::Handle { expected, found: Some(found) } => {
                write!(f, "the handle is a live {found}, not a {expected}: nothing was read through it")
            }
            Failure::Handle { expected, found: None } => write!(
                f,
                "the handle is not a live {expected}: freed already, or never made by hya; nothing was read through it"
            ),
            Failure::Panic(what) => write!(f, "internal error (a bug in hya, please report it): {what}"),
            Failure::CoreInRow { row, error } => write!(f, "row {row}: {error}"),
        }
    }
}

impl From<hya_core::Error> for Failure {
    fn from(e: hya_core::Error) -> Self {
        Failure::Core(e)
    }
}

/// The most bytes a message keeps (longer ones are cut at a character boundary).
pub const HYA_MESSAGE_CAPACITY: usize = 512;

/// A NUL-terminated message in a fixed buffer: writing one never allocates.
#[derive(Debug, Clone)]
pub(crate) struct Message {
    bytes: [u8; HYA_MESSAGE_CAPACITY],
    len: usize,
}

impl Default for Message {
    fn default() -> Self {
        Self { bytes: [0; HYA_MESSAGE_CAPACITY], len: 0 }
    }
}

impl Write for Message {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let room = HYA_MESSAGE_CAPACITY - 1 - self.len;
        let mut take = s.len().min(room);
        while !s.is_char_boundary(take) {
            take -= 1;
        }
        let text = &s.as_bytes()[..take];
        // An interior NUL would cut the message short in C: shown as a space instead.
        for (slot, &b) in self.bytes[self.len..self.len + take].iter_mut().zip(text) {
            *slot = if b == 0 { b' ' } else { b };
        }
        self.len += take;
        self.bytes[self.len] = 0;
        Ok(())
    }
}

impl Message {
    /// Replaces the message by `failure`'s text.
    pub(crate) fn set(&mut self, failure: &Failure) {
        self.len = 0;
        self.bytes[0] = 0;
        // Writing into a fixed buffer cannot fail (it truncates instead).
        let _ = write!(self, "{failure}");
    }

    /// The message as a C string owned by `self`.
    pub(crate) fn as_ptr(&self) -> *const c_char {
        self.bytes.as_ptr().cast()
    }
}

thread_local! {
    static LAST_ERROR: RefCell<Message> = RefCell::new(Message::default());
}

/// Records `failure` as this thread's last error and returns its status.
pub(crate) fn fail_globally(failure: &Failure) -> HyaStatus {
    LAST_ERROR.with(|m| m.borrow_mut().set(failure));
    failure.status()
}

/// This thread's last error, as a C string valid until the next hya call on this thread.
pub(crate) fn last_error_ptr() -> *const c_char {
    LAST_ERROR.with(|m| m.borrow().as_ptr())
}

/// Runs `work`, turning a panic into [`Failure::Panic`].
pub(crate) fn guarded<T>(work: impl FnOnce() -> Result<T, Failure>) -> Result<T, Failure> {
    catch_unwind(AssertUnwindSafe(work)).unwrap_or_else(|payload| {
        let what = payload
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic without a message".to_owned());
        Err(Failure::Panic(what))
    })
}

/// A handle that keeps the message of its last failed call.
pub(crate) trait Handle: 'static {
    /// The handle type's name in the header (`HyaModel`), for messages.
    const KIND: &'static str;
    /// Where its messages go.
    fn message(&mut self) -> &mut Message;
    /// Its last message.
    fn message_ref(&self) -> &Message;
}

/// The message of `handle`'s last failed call, or a static text if it is not a live handle of
/// kind `H`.
///
/// # Safety
/// As [`borrow_live`].
pub(crate) unsafe fn last_message<H: Handle>(handle: *const H) -> *const c_char {
    // SAFETY: the caller's contract.
    match unsafe { borrow_live("handle", handle) } {
        Ok(h) => h.message_ref().as_ptr(),
        Err(_) => {
            c"not a live handle of this kind: null, freed already, of another kind, or never made by hya".as_ptr()
        }
    }
}

/// Every handle this library made and has not freed: its address and kind ([`Handle::KIND`]).
/// Each call checks its handle here before reading through it, so a handle of the wrong kind, a
/// double free or a freed handle is an error status instead of undefined behaviour. (A handle
/// freed and a new one made at the same address cannot be told apart: the registry knows
/// addresses, not the caller's intent.)
static LIVE: RwLock<BTreeMap<usize, &'static str>> = RwLock::new(BTreeMap::new());

/// The registry to read, whatever a panicking thread left it as (its entries are inserted and
/// removed whole, so a poisoned lock still guards a consistent map).
fn live_handles() -> std::sync::RwLockReadGuard<'static, BTreeMap<usize, &'static str>> {
    LIVE.read().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// The registry to change (creation and freeing only).
fn live_handles_mut() -> std::sync::RwLockWriteGuard<'static, BTreeMap<usize, &'static str>> {
    LIVE.write().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// `Ok` if `handle` is a live handle of kind `H`; null is [`Failure::Null`].
pub(crate) fn live<H: Handle>(name: &'static str, handle: *const H) -> Result<(), Failure> {
    if handle.is_null() {
        return Err(Failure::Null(name));
    }
    match live_handles().get(&(handle as usize)) {
        Some(&kind) if kind == H::KIND => Ok(()),
        found => Err(Failure::Handle { expected: H::KIND, found: found.copied() }),
    }
}

/// The handle behind `handle` to read, once [`live`] says it is one of kind `H`.
///
/// # Safety
/// `handle` is null or was made by this library (the registry checks which and whether it is
/// still live); it is not being freed or used mutably by another thread.
pub(crate) unsafe fn borrow_live<'a, H: Handle>(name: &'static str, handle: *const H) -> Result<&'a H, Failure> {
    live(name, handle)?;
    // SAFETY: a live handle of kind `H`, by the registry; the caller's contract for the rest.
    Ok(unsafe { &*handle })
}

/// Runs `work` on the handle behind `handle`: a null handle fails into the thread's last error,
/// any other failure (a panic included) into the handle's own message.
///
/// # Safety
/// `handle` is null or was made by this library (the registry checks which and whether it is
/// still live), and is not in use elsewhere.
pub(crate) unsafe fn on_handle<H: Handle>(
    handle: *mut H,
    work: impl FnOnce(&mut H) -> Result<(), Failure>,
) -> HyaStatus {
    if let Err(failure) = live("handle", handle) {
        return fail_globally(&failure);
    }
    // SAFETY: a live handle of kind `H` (checked above); the caller's contract for the rest.
    let h = unsafe { &mut *handle };
    match guarded(|| work(&mut *h)) {
        Ok(()) => HyaStatus::HyaOk,
        Err(failure) => {
            h.message().set(&failure);
            failure.status()
        }
    }
}

/// Creates a handle with `make` and stores it in `*out` (null on failure); failures go to the
/// thread's last error.
///
/// # Safety
/// `out` is null or valid for one pointer write.
pub(crate) unsafe fn create<H: Handle>(out: *mut *mut H, make: impl FnOnce() -> Result<H, Failure>) -> HyaStatus {
    if out.is_null() {
        return fail_globally(&Failure::Null("out"));
    }
    let made = guarded(make);
    // SAFETY: checked non-null above; the caller's contract makes it writable.
    unsafe {
        *out = core::ptr::null_mut();
    }
    match made {
        Ok(handle) => {
            let handle = Box::into_raw(Box::new(handle));
            live_handles_mut().insert(handle as usize, H::KIND);
            // SAFETY: as above.
            unsafe {
                *out = handle;
            }
            HyaStatus::HyaOk
        }
        Err(failure) => fail_globally(&failure),
    }
}

/// Frees a handle made by [`create`]; null is a no-op. A pointer that is not a live handle of
/// kind `H` (freed already, of another kind, never made by hya) is left alone, and the thread's
/// last error says so.
///
/// # Safety
/// `handle` is null or was made by this library, and is not used by another thread meanwhile.
pub(crate) unsafe fn destroy<H: Handle>(handle: *mut H) {
    if handle.is_null() {
        return;
    }
    let mut live = live_handles_mut();
    if live.get(&(handle as usize)) != Some(&H::KIND) {
        let found = live.get(&(handle as usize)).copied();
        drop(live);
        fail_globally(&Failure::Handle { expected: H::KIND, found });
        return;
    }
    live.remove(&(handle as usize));
    drop(live);
    // SAFETY: a live handle of kind `H` made by `create`, now out of the registry; a panic in a
    // destructor stays on this side.
    let _ = catch_unwind(AssertUnwindSafe(|| drop(unsafe { Box::from_raw(handle) })));
}
