// ShortCut's uniforms and key words, declared once for its depth pass, its hair entry and its resolve. Mirrors
// `render::transparency::shortcut::ShortcutUniforms` (a test compares the layouts).
struct ShortcutUniforms {
    // Nearest fragments kept per pixel (1..8): the key words and slots per pixel.
    k: u32,
    // Viewport width in pixels (the resolve has no frame uniforms).
    width: u32,
    // 1: the K nearest are averaged (TressFX 4.x as shipped), 0: blended front to back.
    average_front: u32,
    pad0: u32,
}

// A key word no depth has: the slot is empty (the depth pass's atomicMin keeps it for the smaller depths).
const SHORTCUT_EMPTY: u32 = 0xffffffffu;
// A key word no depth has: a hair fragment has taken the slot.
const SHORTCUT_TAKEN: u32 = 0xfffffffeu;

// The key of a depth: its f32 bits, which order like the value for depths >= 0 (abs() turns -0.0 into +0.0).
fn shortcut_key(depth: f32) -> u32 {
    return bitcast<u32>(abs(depth));
}
