// `render.hair_model`'s values (`shading::HairModel::uniform`; a test compares them).
const HAIR_MODEL_ABSORBER: u32 = 0u;
const HAIR_MODEL_FIBRES: u32 = 1u;
