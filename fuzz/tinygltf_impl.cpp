// tinygltf and stb_image compiled into the fuzz target, from the same Debian headers the
// normal build links as libtinygltf.so/libstb.so: instrumented, the fuzzer sees coverage and
// the sanitizers see memory errors inside them too, not only in Prism's code.
#define TINYGLTF_IMPLEMENTATION
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <tiny_gltf.h>
