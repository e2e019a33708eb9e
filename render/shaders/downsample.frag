#version 330 core
// Supersampling's resolve: each output pixel is the tent-filtered mean of
// the u_factor x u_factor samples under it and half a pixel around them
// (the filter the styling paper asks for: a box alone leaves jaggies on
// thin bright strands).
uniform sampler2D u_source;
uniform int u_factor;
out vec4 o_color;
void main() {
  ivec2 size = textureSize(u_source, 0);
  vec2 centre = gl_FragCoord.xy * float(u_factor);  // in source pixels
  float reach = float(u_factor);                    // tent half-width: one output pixel
  int n = u_factor;
  vec3 sum = vec3(0.0);
  float wsum = 0.0;
  for (int y = -n; y < n; ++y)
    for (int x = -n; x < n; ++x) {
      vec2 s = floor(centre) + vec2(x, y) + 0.5;
      vec2 d = abs(s - centre) / reach;
      float w = max(0.0, 1.0 - d.x) * max(0.0, 1.0 - d.y);
      ivec2 q = clamp(ivec2(s), ivec2(0), size - 1);
      sum += w * texelFetch(u_source, q, 0).rgb;
      wsum += w;
    }
  o_color = vec4(sum / max(wsum, 1e-8), 1.0);
}
