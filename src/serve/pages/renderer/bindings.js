// Where the renderer's shaders find their uniform blocks and samplers. GLSL ES 3.00 has no binding
// qualifier: every program is told these when it is linked (BrowserRenderer.program).

// Each uniform block's binding point.
export const BLOCK_BINDINGS = { Frame: 0, Lights: 1, Objects: 2, ShadowViews: 3, AnalyticParameters: 4, EnvironmentAlbedo: 5 };

// The texture units of the shaders' samplers (the resolve's colour shares the shadow cubes' unit).
export const TEXTURE_UNITS = { shadow_maps: 0, measured_tables: 1, environment_map: 2, environment_prefiltered: 3, colour: 0, probe_directions: 4, albedo_cells: 4 };
