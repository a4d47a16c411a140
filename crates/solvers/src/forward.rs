//! Forwarding of a trait's methods to another value: the body of an `impl Trait for &S` whose
//! methods all call the same method of `S` (a borrowed system stands for the system: many
//! integrators, one per basin cell, say, can borrow one model instead of cloning its tables), or
//! of a wrapper whose methods call those of the value it wraps.

/// Methods that call the method of the same name, with the same arguments, of `**self`
/// (`to referent`: the body of an `impl Trait for &S`) or of the field `self.f` (`to field f`: a
/// wrapper), each `#[inline(always)]`; the methods are listed by signature, each ended by `;`
/// (the associated types and any other methods are written beside it).
///
/// ```
/// trait Area {
///     fn area(&self, scale: f64) -> f64;
/// }
/// struct Square(f64);
/// impl Area for Square {
///     fn area(&self, scale: f64) -> f64 {
///         scale * self.0 * self.0
///     }
/// }
/// impl<S: Area> Area for &S {
///     geardyn_solvers::forward_methods! { to referent;
///         fn area(&self, scale: f64) -> f64;
///     }
/// }
/// struct Named(&'static str, Square);
/// impl Area for Named {
///     geardyn_solvers::forward_methods! { to field 1;
///         fn area(&self, scale: f64) -> f64;
///     }
/// }
/// assert_eq!((&Square(2.0)).area(0.5), 2.0);
/// assert_eq!(Named("two", Square(2.0)).area(0.5), 2.0);
/// ```
#[macro_export]
macro_rules! forward_methods {
    (to referent; $(fn $name:ident(&self $(, $arg:ident: $ty:ty)* $(,)?) $(-> $ret:ty)?;)*) => {
        $(
            #[inline(always)]
            fn $name(&self $(, $arg: $ty)*) $(-> $ret)? {
                (**self).$name($($arg),*)
            }
        )*
    };
    (to field $field:tt; $(fn $name:ident(&self $(, $arg:ident: $ty:ty)* $(,)?) $(-> $ret:ty)?;)*) => {
        $(
            #[inline(always)]
            fn $name(&self $(, $arg: $ty)*) $(-> $ret)? {
                self.$field.$name($($arg),*)
            }
        )*
    };
}
