//! Forwarding through a shared reference: the body of an `impl Trait for &S` whose methods all
//! call the same method of `S` (a borrowed system stands for the system: many integrators, one
//! per basin cell, say, can borrow one model instead of cloning its tables).

/// Methods that call the method of the same name of `**self` with the same arguments, each
/// `#[inline(always)]`: the body of an `impl Trait for &S`, the methods listed by signature, each
/// ended by `;` (the associated types are written beside it).
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
///     geardyn_solvers::forward_to_referent! {
///         fn area(&self, scale: f64) -> f64;
///     }
/// }
/// assert_eq!((&Square(2.0)).area(0.5), 2.0);
/// ```
#[macro_export]
macro_rules! forward_to_referent {
    ($(fn $name:ident(&self $(, $arg:ident: $ty:ty)* $(,)?) $(-> $ret:ty)?;)*) => {
        $(
            #[inline(always)]
            fn $name(&self $(, $arg: $ty)*) $(-> $ret)? {
                (**self).$name($($arg),*)
            }
        )*
    };
}
