
yw
{"asset":{"version":"2.0"}}X
env.hdrM#?RADIANCE
FORMAT=32-bit_rle_rgbe

-Y 2 +X 4
@Ä¿Ç@Ä¿Ç@Ä¿Ç@Ä¿Ç@Ä¿Ç@Ä¿Ç@Ä¿Ç@Ä¿Ç*partitionedäx.gltf¢env.hdr∫
radius*auto