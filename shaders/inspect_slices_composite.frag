// `inspect --render slices` composited by tiles (inspect_slices_composite.comp):
// its picture, premultiplied, blended over the frame like the slabs it
// stands for (the draw's viewport starts at the picture's corner).
layout(binding = kSliceTilesPictureUnit) uniform sampler2D picture;
layout(location = 0) out vec4 colour;

void main() { colour = texelFetch(picture, ivec2(gl_FragCoord.xy), 0); }
