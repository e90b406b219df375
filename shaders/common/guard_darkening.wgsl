// Local self-shadowing of guard hairs (Andersen et al. 2016 §3.1 after Neulander & van de Panne 1998): the
// transmittance of the undercoat column above a point `height` above the base, `shell_height` thick, of
// extinction `sigma` per world unit. CPU model: `fur::darkening::darkening`.
#include "common/visibility.wgsl"

fn guard_darkening(height: f32, shell_height: f32, sigma: f32) -> f32 {
    return transmittance(sigma * max(shell_height - height, 0.0));
}
