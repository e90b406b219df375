// One light-space fragment in a texel's list of the reference A-buffer (render::passes::abuffer, NODE_BYTES):
// written by abuffer.wgsl, read by the reference lookup and by the compressors that build their maps from the
// lists (AVSM, compressed deep shadow maps).
struct ListNode {
    depth: f32,
    alpha: f32,
    segment: u32,
    // Index + 1 of the next node of the texel's list; 0 ends the list.
    next: u32,
}
