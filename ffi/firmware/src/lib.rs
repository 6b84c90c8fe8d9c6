//! What every image of this package shares: the interrupt vector table.
//!
//! Without a device crate, cortex-m-rt fills 240 interrupt vectors (960
//! bytes of flash); the MPS2 AN386 has 32. A real firmware has its own
//! device's table: this one is the emulated board's, so that the images'
//! flash is what the model costs plus what any firmware carries.

#![no_std]

/// The 32 external interrupt vectors, every one the default handler
/// (the images enable no interrupt).
#[link_section = ".vector_table.interrupts"]
#[no_mangle]
pub static __INTERRUPTS: [unsafe extern "C" fn(); 32] = [{
    unsafe extern "C" {
        fn DefaultHandler();
    }
    DefaultHandler
}; 32];
