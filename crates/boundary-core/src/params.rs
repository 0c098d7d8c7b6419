//! Parameters declared once: [`declare_params!`](crate::declare_params) turns one line per
//! parameter (its key, type, default, check and description) into the typed struct, its
//! `Default`, the validation a method's `try_new` runs, the `key=value` parsing of the
//! registry and the listing of `boundary methods`.
//!
//! ```
//! use boundary_core::params::ParamSet;
//!
//! boundary_core::declare_params! {
//!     /// The parameters of `lonely`.
//!     #[derive(Debug, Clone, PartialEq)]
//!     pub struct LonelyParams for "lonely" {
//!         /// How many neighbours a particle may have and still be lonely.
//!         pub friends: u32 = 0, check::int_in(0, 3),
//!             "neighbours within r that still count as lonely";
//!     }
//! }
//!
//! let p = LonelyParams::from_pairs(&[("friends", "2")]).unwrap();
//! assert_eq!(p.friends, 2);
//! assert_eq!(p.listing().to_string(), "friends=2");
//! let err = LonelyParams::from_pairs(&[("friends", "9")]).unwrap_err();
//! assert_eq!(
//!     err.to_string(),
//!     "method 'lonely': invalid value '9' for 'friends': must be an integer in 0..=3"
//! );
//! ```

use crate::{ParamError, Params};

/// A value a parameter can take, with its text form (`--set key=TEXT`).
pub trait ParamValue: Sized {
    /// The value of `text`. `Err(None)`: `text` is no value of the type, and the parameter's
    /// check gives the reason (a number that does not parse is reported like an
    /// out-of-range one); `Err(Some(reason))`: the type's own reason (a kernel's name).
    fn from_text(text: &str) -> Result<Self, Option<String>>;
    /// The text form, which [`ParamValue::from_text`] accepts back.
    fn to_text(&self) -> String;
}

impl ParamValue for f64 {
    fn from_text(text: &str) -> Result<Self, Option<String>> {
        text.trim().parse().map_err(|_| None)
    }
    fn to_text(&self) -> String {
        self.to_string()
    }
}

/// The unsigned integers: a text that is not a whole number is reported with the check's
/// reason.
macro_rules! unsigned_param_value {
    ($($t:ty),*) => {$(
        impl ParamValue for $t {
            fn from_text(text: &str) -> Result<Self, Option<String>> {
                text.trim().parse().map_err(|_| None)
            }
            fn to_text(&self) -> String {
                self.to_string()
            }
        }
    )*};
}
unsigned_param_value!(u8, u32, usize);

/// A switch: `on` or `off` (also `true`/`false`, `1`/`0`, `yes`/`no`).
impl ParamValue for bool {
    fn from_text(text: &str) -> Result<Self, Option<String>> {
        match text.trim() {
            "on" | "true" | "1" | "yes" => Ok(true),
            "off" | "false" | "0" | "no" => Ok(false),
            _ => Err(None),
        }
    }
    fn to_text(&self) -> String {
        if *self { "on" } else { "off" }.to_owned()
    }
}

/// `auto` (`None`: the method derives the value) or a value.
impl<T: ParamValue> ParamValue for Option<T> {
    fn from_text(text: &str) -> Result<Self, Option<String>> {
        match text.trim() {
            "auto" => Ok(None),
            value => T::from_text(value).map(Some),
        }
    }
    fn to_text(&self) -> String {
        self.as_ref().map_or_else(|| "auto".to_owned(), T::to_text)
    }
}

/// What a parameter accepts, and the reason given when a value is refused.
pub struct Check<T> {
    accepts: Box<dyn Fn(&T) -> bool>,
    reason: String,
}

impl<T> std::fmt::Debug for Check<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Check")
            .field("reason", &self.reason)
            .finish()
    }
}

impl<T> Check<T> {
    /// The check `accepts`, refusing with `reason` (what the parameter must be).
    pub fn new(accepts: impl Fn(&T) -> bool + 'static, reason: impl Into<String>) -> Self {
        Check {
            accepts: Box::new(accepts),
            reason: reason.into(),
        }
    }

    /// The same check with another reason (where a method's message is worded its own way).
    #[must_use]
    pub fn because(self, reason: impl Into<String>) -> Self {
        Check {
            reason: reason.into(),
            ..self
        }
    }

    /// Whether `value` is accepted.
    pub fn accepts(&self, value: &T) -> bool {
        (self.accepts)(value)
    }

    /// What the parameter must be.
    pub fn reason(&self) -> &str {
        &self.reason
    }
}

/// The shared checks: one wording for each kind of range.
pub mod check {
    use super::Check;

    /// An integer in `lo..=hi`.
    pub fn int_in(lo: u32, hi: u32) -> Check<u32> {
        Check::new(
            move |v| (lo..=hi).contains(v),
            format!("must be an integer in {lo}..={hi}"),
        )
    }

    /// A finite number `>= 0`.
    pub fn non_negative() -> Check<f64> {
        Check::new(
            |v: &f64| v.is_finite() && *v >= 0.0,
            "must be a number >= 0",
        )
    }

    /// A number in `(lo, hi]`.
    pub fn open_closed(lo: f64, hi: f64) -> Check<f64> {
        Check::new(
            move |v: &f64| *v > lo && *v <= hi,
            format!("must be in ({lo}, {hi}]"),
        )
    }

    /// A number in `(lo, hi)`.
    pub fn open(lo: f64, hi: f64) -> Check<f64> {
        Check::new(
            move |v: &f64| *v > lo && *v < hi,
            format!("must be in ({lo}, {hi})"),
        )
    }

    /// A number in `[lo, hi]`.
    pub fn closed(lo: f64, hi: f64) -> Check<f64> {
        Check::new(
            move |v: &f64| *v >= lo && *v <= hi,
            format!("must be in [{lo}, {hi}]"),
        )
    }

    /// `auto` (`None`), or a value that `inner` accepts; `reason` says both.
    pub fn auto_or<T: 'static>(inner: Check<T>, reason: &str) -> Check<Option<T>> {
        Check::new(
            move |v: &Option<T>| v.as_ref().is_none_or(|v| inner.accepts(v)),
            reason,
        )
    }

    /// At most `hi` (a count).
    pub fn at_most<T: PartialOrd + Copy + 'static>(hi: T, reason: &str) -> Check<T> {
        Check::new(move |v: &T| *v <= hi, reason)
    }

    /// Every value of the type (a choice whose parsing already refuses the rest).
    pub fn any<T>(reason: &str) -> Check<T> {
        Check::new(|_| true, reason)
    }
}

/// A parameter struct written by [`declare_params!`](crate::declare_params).
pub trait ParamSet: Default + Clone {
    /// The method the parameters belong to (in error messages).
    const METHOD: &'static str;
    /// The keys, in declaration order.
    const KEYS: &'static [&'static str];

    /// The first parameter that its check refuses, as [`ParamError::Invalid`].
    fn check(&self) -> Result<(), ParamError>;

    /// Sets the parameter `key` from `text`: `Ok(false)` when there is no such key; the error
    /// is the reason when `text` is no value of the parameter (the check is not run).
    fn set(&mut self, key: &str, text: &str) -> Result<bool, String>;

    /// The parameters with their current values and defaults.
    fn listing(&self) -> Params;

    /// The defaults with `pairs` applied in order, each checked at once: the error names the
    /// first pair that fails and quotes its value as given; an unknown key lists the keys.
    fn from_pairs(pairs: &[(&str, &str)]) -> Result<Self, ParamError> {
        let mut params = Self::default();
        for &(key, text) in pairs {
            match params.set(key, text) {
                Ok(true) => {}
                Ok(false) => return Err(ParamError::unknown(Self::METHOD, key, Self::KEYS)),
                Err(reason) => return Err(ParamError::invalid(Self::METHOD, key, text, reason)),
            }
            params.check().map_err(|e| match e {
                ParamError::Invalid {
                    method,
                    key: named,
                    reason,
                    ..
                } if named == key => ParamError::invalid(method, key, text, reason),
                other => other,
            })?;
        }
        Ok(params)
    }
}

/// Parses `text` for a parameter checked by `check`: the type's reason, or the check's when
/// the text is no value of the type. Used by [`declare_params!`](crate::declare_params).
pub fn parse_checked<T: ParamValue>(text: &str, check: &Check<T>) -> Result<T, String> {
    T::from_text(text).map_err(|reason| reason.unwrap_or_else(|| check.reason().to_owned()))
}

/// Declares a method's parameters once: for each, its doc comment, key (the field name), type,
/// default, check (a [`Check`], usually one of [`check`], which the macro brings into scope
/// as `check::…`) and one-line description. Writes the
/// struct, its `Default` and its [`ParamSet`] (validation, `key=value` parsing, listing).
/// Every type implements [`ParamValue`]. See the [module docs](crate::params).
#[macro_export]
macro_rules! declare_params {
    (
        $(#[$attr:meta])*
        $vis:vis struct $name:ident for $method:literal {
            $(
                $(#[$fattr:meta])*
                $fvis:vis $field:ident : $ty:ty = $default:expr, $check:expr, $desc:expr;
            )*
        }
    ) => {
        $(#[$attr])*
        $vis struct $name {
            $(
                $(#[$fattr])*
                $fvis $field: $ty,
            )*
        }

        impl ::core::default::Default for $name {
            fn default() -> Self {
                $name { $($field: $default,)* }
            }
        }

        impl $crate::params::ParamSet for $name {
            const METHOD: &'static str = $method;
            const KEYS: &'static [&'static str] = &[$(stringify!($field)),*];

            fn check(&self) -> ::core::result::Result<(), $crate::ParamError> {
                #[allow(unused_imports)]
                use $crate::params::{check, ParamValue};
                $(
                    let rule: $crate::params::Check<$ty> = $check;
                    if !rule.accepts(&self.$field) {
                        return Err($crate::ParamError::invalid(
                            $method,
                            stringify!($field),
                            &self.$field.to_text(),
                            rule.reason(),
                        ));
                    }
                )*
                Ok(())
            }

            fn set(&mut self, key: &str, text: &str) -> ::core::result::Result<bool, String> {
                #[allow(unused_imports)]
                use $crate::params::check;
                match key {
                    $(
                        stringify!($field) => {
                            let rule: $crate::params::Check<$ty> = $check;
                            self.$field = $crate::params::parse_checked(text, &rule)?;
                            Ok(true)
                        }
                    )*
                    _ => Ok(false),
                }
            }

            fn listing(&self) -> $crate::Params {
                #[allow(unused_imports)]
                use $crate::params::ParamValue;
                let defaults = <Self as ::core::default::Default>::default();
                $crate::Params(vec![$(
                    $crate::ParamInfo {
                        name: stringify!($field),
                        value: self.$field.to_text(),
                        default: defaults.$field.to_text(),
                        description: $desc,
                    },
                )*])
            }
        }
    };
}

/// A method whose parameters are a [`ParamSet`]: what the facade's registry needs to build it
/// from `key=value` text. One line per method: `impl_configurable!(IaDetector, IaParams)`.
pub trait Configurable: crate::Method + Sized + 'static {
    /// The typed parameters.
    type Params: ParamSet;
    /// The detector with `params`, checked (the method's `try_new`).
    fn from_params(params: Self::Params) -> Result<Self, ParamError>;
}

/// Implements [`Configurable`] for a detector with an inherent
/// `try_new(Params) -> Result<Self, ParamError>`.
#[macro_export]
macro_rules! impl_configurable {
    ($detector:ty, $params:ty) => {
        impl $crate::params::Configurable for $detector {
            type Params = $params;
            fn from_params(params: $params) -> ::core::result::Result<Self, $crate::ParamError> {
                <$detector>::try_new(params)
            }
        }
    };
}

/// Writes, for a detector whose only field is `params` (its declared parameters), the
/// checked constructor `try_new`, the accessor `params()` and [`Configurable`]. A detector
/// with a check across fields writes its `try_new` itself and uses
/// [`impl_configurable!`](crate::impl_configurable).
#[macro_export]
macro_rules! impl_detector_params {
    ($detector:ident, $params:ty) => {
        impl $detector {
            /// The detector with `params`, each checked as declared (a value is never
            /// clamped); the error names the first field that fails and says what it must be.
            pub fn try_new(params: $params) -> ::core::result::Result<Self, $crate::ParamError> {
                $crate::params::ParamSet::check(&params)?;
                Ok($detector { params })
            }

            /// The parameters.
            pub fn params(&self) -> &$params {
                &self.params
            }
        }

        $crate::impl_configurable!($detector, $params);
    };
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::ParamSet;

    crate::declare_params! {
        /// Two parameters.
        #[derive(Debug, Clone, PartialEq)]
        struct Two for "two" {
            /// A depth.
            depth: u32 = 6, check::int_in(1, 16), "a depth";
            /// A tolerance.
            tie: f64 = 0.0, check::non_negative().because("a finite number >= 0"), "a tie";
        }
    }

    #[test]
    fn pairs_apply_in_order_and_the_first_failure_is_reported_as_given() {
        assert_eq!(Two::default(), Two { depth: 6, tie: 0.0 });
        let p = Two::from_pairs(&[("depth", "3"), ("tie", "1e-9"), ("depth", " 4")]).unwrap();
        assert_eq!(
            p,
            Two {
                depth: 4,
                tie: 1e-9
            }
        );
        assert_eq!(p.listing().to_string(), "depth=4, tie=0.000000001");
        assert_eq!(p.listing().0[0].default, "6");
        let err = Two::from_pairs(&[("depth", "x"), ("tie", "-1")]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "method 'two': invalid value 'x' for 'depth': must be an integer in 1..=16"
        );
        let err = Two::from_pairs(&[("tie", " -1")]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "method 'two': invalid value ' -1' for 'tie': a finite number >= 0"
        );
        let err = Two::from_pairs(&[("nope", "1")]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "method 'two' has no parameter 'nope' (parameters: depth, tie)"
        );
        assert!(Two {
            depth: 17,
            tie: 0.0
        }
        .check()
        .is_err());
        assert!(Two {
            depth: 1,
            tie: f64::NAN
        }
        .check()
        .is_err());
        assert!(Two::default().check().is_ok());
    }
}
