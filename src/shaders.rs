//! The SPIR-V that build.rs compiled from `shaders/`, looked up by key: `"mesh.vert"`,
//! `"surface.frag:<method id>"`, `"pyramid.comp:r16"`, ...

/// Forces 4-byte alignment on embedded SPIR-V so it can be viewed as `u32` words in place.
#[repr(C, align(4))]
pub(crate) struct Aligned<T: ?Sized>(pub T);

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// The SPIR-V words of shader variant `key`, if build.rs produced it.
pub fn spirv(key: &str) -> Option<&'static [u32]> {
    SHADERS
        .iter()
        .find(|(k, _)| *k == key)
        .map(|(_, blob)| bytemuck::cast_slice(&blob.0))
}

/// Every compiled variant's key.
pub fn keys() -> impl Iterator<Item = &'static str> {
    SHADERS.iter().map(|(k, _)| *k)
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_variant_is_spirv() {
        assert!(super::keys().count() >= 3);
        for key in super::keys() {
            let words = super::spirv(key).expect("listed key resolves");
            assert_eq!(
                words[0], 0x0723_0203,
                "{key} starts with the SPIR-V magic number"
            );
        }
        assert!(super::spirv("no such shader").is_none());
    }
}
