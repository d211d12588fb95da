// `inspect --render slices` composited by tiles of the picture
// (src/render/slice_tiles.h): one work group a 16 x 16 tile, one thread a
// pixel. The tile's slabs come nearest first (inspect_slices_tiles.comp's
// sorted pairs), in batches of 256: each thread sets up one slab in shared
// memory (its frame, the eye and light in it) and sets its bit in the
// bitmap of every pixel of the tile whose centre its screen box holds
// (slabs.glsl's slabPixelRange); then each pixel walks its own bits,
// in order, casting its ray through those slabs (slabs.glsl's
// slabBoxInterval and slabColour, as inspect_slices.frag's points do), and
// blends front to back: colour += transmittance * the slab's,
// transmittance *= 1 - its alpha. Back to front "over", the same sum.
// Slabs far below a pixel are many to a tile (about 100 k for a whole
// garment of 41 M slices at 1280x720) and each covers a few of its pixels:
// a pixel visits the few whose box holds it, not all 256 of a batch. A pixel
// whose transmittance falls below kOpaque takes no more, and the group
// stops once all of its pixels have. The picture is written premultiplied
// (colour, 1 - transmittance), every pixel of the tile.

#include "slabs.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

layout(binding = kSliceTableUnit) uniform samplerBuffer slices; // per slice: (centre, thickness), (tangent, place in its run)
layout(binding = kSliceSpansUnit) uniform usamplerBuffer spans; // per slice: the slices its slab stands for
layout(std430, binding = kSliceTileEntriesBinding) readonly buffer Entries { uint entrySlices[]; };
layout(std430, binding = kSliceTileRangesBinding) readonly buffer Ranges { uint ranges[]; };
layout(binding = kSliceTilesImageUnit, rgba16f) writeonly uniform image2D picture;

// The look, named as the raster programs name it (slice_renderer.cpp sets both).
uniform mat4 viewProjection;
uniform mat4 inverseViewProjection;
uniform vec2 viewportPixels; // the picture's size
uniform int tilesX;          // tiles across it
uniform vec3 eye;
uniform vec3 lightDirection; // unit, towards the light
uniform float radius;        // the yarn's
uniform float opacityPerVoxel; // extinction along the ray, per voxel of yarn crossed
uniform float twist;           // radians per voxel of yarn the fibres turn by
uniform vec3 albedo;

// Below this transmittance a pixel changes by less than a 16-bit step.
const float kOpaque = 1.0 / 65536.0;
const uint kBatch = 256u, kPixels = 256u, kWords = kBatch / 32u;

shared vec4 slabRight[kBatch], slabUp[kBatch], slabTangent[kBatch]; // w: the half size along each
shared vec4 slabEye[kBatch];   // xyz: the eye in the slab's frame
shared vec4 slabLight[kBatch]; // xyz: the light in the slab's frame
// Per pixel, a bit a slab of the batch whose box holds it: word w of pixel p
// at w * kPixels + p (a pixel's words in the same banks as its neighbours').
// Each pixel clears its own words as it reads them.
shared uint pixelSlabs[kWords * kPixels];
shared uint opaquePixels;

void main() {
    uint lid = gl_LocalInvocationIndex;
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    bool inside = pixel.x < int(viewportPixels.x) && pixel.y < int(viewportPixels.y);
    uint tile = gl_WorkGroupID.y * uint(tilesX) + gl_WorkGroupID.x;
    uint first = ranges[2u * tile], end = ranges[2u * tile + 1u];
    vec2 corner = vec2(gl_WorkGroupID.xy * 16u); // the tile's lower left, pixels

    vec2 centre = vec2(pixel) + 0.5;
    vec2 ndc = centre / viewportPixels * 2.0 - 1.0;
    vec4 near = inverseViewProjection * vec4(ndc, -1.0, 1.0), far = inverseViewProjection * vec4(ndc, 1.0, 1.0);
    vec3 ray = normalize(far.xyz / far.w - near.xyz / near.w);

    vec3 colour = vec3(0.0);
    float transmittance = 1.0;
    bool done = !inside, counted = false;
    if (lid == 0u) opaquePixels = 0u;
    for (uint w = 0u; w < kWords; ++w) pixelSlabs[w * kPixels + lid] = 0u;
    for (uint base = first; base < end; base += kBatch) {
        barrier(); // the last batch is read and every bitmap cleared
        if (base + lid < end) {
            Slab s = sliceSlab(slices, spans, entrySlices[base + lid], radius);
            mat3 toSlab = transpose(s.frame);
            slabRight[lid] = vec4(s.frame[0], s.halfSize.x);
            slabUp[lid] = vec4(s.frame[1], s.halfSize.y);
            slabTangent[lid] = vec4(s.frame[2], s.halfSize.z);
            slabEye[lid] = vec4(toSlab * (eye - s.centre), 0.0);
            slabLight[lid] = vec4(toSlab * lightDirection, 0.0);
            vec4 box;
            slabPixelBox(s, viewProjection, viewportPixels, box);
            vec4 range = slabPixelRange(box, corner, vec2(15.0)); // the tile's pixels
            ivec2 lo = max(ivec2(range.xy), ivec2(0)), hi = min(ivec2(range.zw), ivec2(15));
            uint word = lid / 32u * kPixels, bit = 1u << (lid % 32u);
            for (int y = lo.y; y <= hi.y; ++y)
                for (int x = lo.x; x <= hi.x; ++x) atomicOr(pixelSlabs[word + uint(y * 16 + x)], bit);
        }
        if (done && !counted) {
            counted = true;
            atomicAdd(opaquePixels, 1u);
        }
        memoryBarrierShared();
        barrier();
        if (opaquePixels == kPixels) break; // every pixel of the tile is done: the same for all
        for (uint w = 0u; w < kWords; ++w) {
            uint bits = pixelSlabs[w * kPixels + lid];
            pixelSlabs[w * kPixels + lid] = 0u;
            for (; bits != 0u && !done; bits &= bits - 1u) {
                uint k = w * 32u + uint(findLSB(bits));
                vec3 localEye = slabEye[k].xyz;
                vec3 d = vec3(dot(ray, slabRight[k].xyz), dot(ray, slabUp[k].xyz), dot(ray, slabTangent[k].xyz));
                vec3 halfSize = vec3(slabRight[k].w, slabUp[k].w, slabTangent[k].w);
                vec2 interval = slabBoxInterval(localEye, d, halfSize);
                interval.x = max(interval.x, 0.0); // from the eye on
                if (!(interval.x < interval.y)) continue;
                vec4 c = slabColour(localEye, d, interval, halfSize.x, opacityPerVoxel, twist, albedo, slabLight[k].xyz);
                colour += transmittance * c.rgb;
                transmittance *= 1.0 - c.a;
                done = transmittance < kOpaque;
            }
        }
    }
    if (inside) imageStore(picture, pixel, vec4(colour, 1.0 - transmittance));
}
