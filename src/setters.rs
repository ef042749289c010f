//! Setters for option structs that are `#[non_exhaustive]`, so that a new option is not a
//! breaking change for code outside relief, yet can still be built in one expression:
//! `RenderOptions::default().with_width(640).with_msaa(4)`.

/// Adds `pub fn <setter>(self, value) -> Self` to `$ty` for each `setter => field: Type`.
macro_rules! with_setters {
    ($ty:ident { $($setter:ident => $field:ident: $t:ty),* $(,)? }) => {
        impl $ty {
            $(
                #[doc = concat!("The same options with `", stringify!($field), "` set to `value`.")]
                #[must_use]
                pub fn $setter(mut self, value: $t) -> Self {
                    self.$field = value;
                    self
                }
            )*
        }
    };
}
