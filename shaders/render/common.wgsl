// Shared by the render pipelines. Keep in sync with src/render/camera.rs (CameraUniform).

struct Camera {
    view_proj: mat4x4<f32>,
    // xyz: eye position (m).
    eye: vec4<f32>,
    // xyz: direction towards the light (unit).
    light_dir: vec4<f32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;

fn shade(base: vec3<f32>, n: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    let l = normalize(camera.light_dir.xyz);
    let view = normalize(camera.eye.xyz - p);
    let diffuse = max(dot(n, l), 0.0);
    let h = normalize(l + view);
    let spec = pow(max(dot(n, h), 0.0), 48.0) * 0.25;
    let sky = 0.5 + 0.5 * n.y;
    let ambient = mix(vec3<f32>(0.12, 0.11, 0.10), vec3<f32>(0.30, 0.32, 0.36), sky);
    return base * (ambient + 0.85 * diffuse) + vec3<f32>(spec);
}
