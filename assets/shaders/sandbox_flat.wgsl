// A flat colour, unlit: the sandbox's floor, pipe and glass walls. The full PBR fragment shader
// costs a software rasterizer more than the whole simulation at this screen coverage.
#import bevy_pbr::forward_io::VertexOutput

@group(#{MATERIAL_BIND_GROUP}) @binding(0) var<uniform> color: vec4<f32>;

@fragment
fn fragment(in: VertexOutput) -> @location(0) vec4<f32> {
    // A little shading from the normal keeps the shapes readable.
    let shade = 0.8 + 0.2 * abs(in.world_normal.y);
    return vec4<f32>(color.rgb * shade, color.a);
}
