// The guard hairs' environment of directional lights (Andersen et al. 2016 §5: 16 lights sampled from an HDR
// map): the strand shading model summed over the frame's `env_count` lights. CPU model:
// `fur::environment::shade` over `fur::environment::Sky::lights`.
#include "common/strand_shading.wgsl"

fn env_shading(tangent: vec3<f32>, to_eye: vec3<f32>, colour: vec3<f32>) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < min(frame.env_count, 64u); i++) {
        sum += strand_shading(tangent, frame.env_to_light[i].xyz, to_eye, colour) * frame.env_radiance[i].xyz;
    }
    return sum;
}
