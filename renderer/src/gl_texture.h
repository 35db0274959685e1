#pragma once
// Private: uploading the procedural textures (textures.h) to the GL.

#include <GL/glcorearb.h>

#include "gl_api.h"
#include "textures.h"

namespace hcpf::renderer::internal {

// Uploads `t` to a new GL_TEXTURE_2D, bound to the active unit, and returns
// it. `repeat`: wrap GL_REPEAT, minified through a mipmap chain whose levels
// are HalveTexture's, uploaded one by one (GL_LINEAR_MIPMAP_NEAREST); else
// GL_CLAMP_TO_EDGE, linear, one level.
//
// Not glGenerateMipmap: the GL leaves its filter to the implementation, and
// they differ. Mesa 22.3's levels are brighter than the rounded mean by about
// 0.37 grey levels per halving (+1.5 at 16 x 16); NVIDIA's are not; the far
// terrain, drawn from the small levels, came out 2 levels apart between the
// two (docs/renderer.md, "The same scene on any GL"). With the levels
// uploaded, every GL samples the same texels.
GLuint UploadTexture(const GlApi& gl, const Texture8& t, bool repeat);

}  // namespace hcpf::renderer::internal
