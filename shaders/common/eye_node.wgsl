// One node of the eye-space per-pixel fragment lists (32 bytes; mirrored by `EyeNode` in
// src/render/transparency/sorted.rs): the stored depth and segment (the total order), the shaded colour and
// alpha, the next node (index + 1, 0 ends the list) and a kind word (0 = strand; the fur combination types its
// fragments with it).
struct EyeNode {
    depth: f32,
    segment: u32,
    r: f32,
    g: f32,
    b: f32,
    alpha: f32,
    next: u32,
    kind: u32,
}
