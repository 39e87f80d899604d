#pragma once
// The GL entry points hlodr uses, loaded per context through GlContext::getProcAddress.
// No global GL symbols: EGL and OSMesa contexts (and several threads, one context each) coexist
// in one process, each with its own table.
#include <GL/glcorearb.h>

#include <string>

namespace renderer {

// X(type-suffix, name): PFNGL<SUFFIX>PROC gl<name>.
#define HLODR_GL_FUNCTIONS(X)                         \
  X(GETSTRING, GetString)                             \
  X(GETINTEGERV, GetIntegerv)                         \
  X(GETERROR, GetError)                               \
  X(VIEWPORT, Viewport)                               \
  X(CLEARCOLOR, ClearColor)                           \
  X(CLEARDEPTH, ClearDepth)                           \
  X(CLEAR, Clear)                                     \
  X(ENABLE, Enable)                                   \
  X(DISABLE, Disable)                                 \
  X(DEPTHFUNC, DepthFunc)                             \
  X(DEPTHMASK, DepthMask)                             \
  X(CLIPCONTROL, ClipControl)                         \
  X(CULLFACE, CullFace)                               \
  X(FINISH, Finish)                                   \
  X(FLUSH, Flush)                                     \
  X(PIXELSTOREI, PixelStorei)                         \
  X(READPIXELS, ReadPixels)                           \
  X(GENFRAMEBUFFERS, GenFramebuffers)                 \
  X(DELETEFRAMEBUFFERS, DeleteFramebuffers)           \
  X(BINDFRAMEBUFFER, BindFramebuffer)                 \
  X(FRAMEBUFFERRENDERBUFFER, FramebufferRenderbuffer) \
  X(CHECKFRAMEBUFFERSTATUS, CheckFramebufferStatus)   \
  X(GENRENDERBUFFERS, GenRenderbuffers)               \
  X(DELETERENDERBUFFERS, DeleteRenderbuffers)         \
  X(BINDRENDERBUFFER, BindRenderbuffer)               \
  X(RENDERBUFFERSTORAGE, RenderbufferStorage)         \
  X(CREATESHADER, CreateShader)                       \
  X(SHADERSOURCE, ShaderSource)                       \
  X(COMPILESHADER, CompileShader)                     \
  X(GETSHADERIV, GetShaderiv)                         \
  X(GETSHADERINFOLOG, GetShaderInfoLog)               \
  X(DELETESHADER, DeleteShader)                       \
  X(CREATEPROGRAM, CreateProgram)                     \
  X(ATTACHSHADER, AttachShader)                       \
  X(LINKPROGRAM, LinkProgram)                         \
  X(GETPROGRAMIV, GetProgramiv)                       \
  X(GETPROGRAMINFOLOG, GetProgramInfoLog)             \
  X(DELETEPROGRAM, DeleteProgram)                     \
  X(USEPROGRAM, UseProgram)                           \
  X(GETUNIFORMLOCATION, GetUniformLocation)           \
  X(UNIFORMMATRIX4FV, UniformMatrix4fv)               \
  X(UNIFORM3FV, Uniform3fv)                           \
  X(UNIFORM4FV, Uniform4fv)                           \
  X(UNIFORM1I, Uniform1i)                             \
  X(UNIFORM1F, Uniform1f)                             \
  X(GENVERTEXARRAYS, GenVertexArrays)                 \
  X(DELETEVERTEXARRAYS, DeleteVertexArrays)           \
  X(BINDVERTEXARRAY, BindVertexArray)                 \
  X(GENBUFFERS, GenBuffers)                           \
  X(DELETEBUFFERS, DeleteBuffers)                     \
  X(BINDBUFFER, BindBuffer)                           \
  X(BUFFERDATA, BufferData)                           \
  X(BUFFERSUBDATA, BufferSubData)                     \
  X(VERTEXATTRIBPOINTER, VertexAttribPointer)         \
  X(ENABLEVERTEXATTRIBARRAY, EnableVertexAttribArray) \
  X(VERTEXATTRIB3F, VertexAttrib3f)                   \
  X(DRAWELEMENTS, DrawElements)                       \
  X(GENTEXTURES, GenTextures)                         \
  X(DELETETEXTURES, DeleteTextures)                   \
  X(BINDTEXTURE, BindTexture)                         \
  X(ACTIVETEXTURE, ActiveTexture)                     \
  X(TEXIMAGE2D, TexImage2D)                           \
  X(TEXPARAMETERI, TexParameteri)                     \
  X(GENERATEMIPMAP, GenerateMipmap)                   \
  X(GENQUERIES, GenQueries)                           \
  X(DELETEQUERIES, DeleteQueries)                     \
  X(BEGINQUERY, BeginQuery)                           \
  X(ENDQUERY, EndQuery)                               \
  X(GETQUERYOBJECTUI64V, GetQueryObjectui64v)         \
  X(FRAMEBUFFERTEXTURE2D, FramebufferTexture2D)       \
  X(DRAWARRAYS, DrawArrays)                           \
  X(DRAWBUFFERS, DrawBuffers)                         \
  X(READBUFFER, ReadBuffer)                           \
  X(UNIFORM2FV, Uniform2fv)                           \
  X(BLENDFUNC, BlendFunc)                             \
  X(COLORMASK, ColorMask)                             \
  X(UNIFORM1UI, Uniform1ui)

struct GlFunctions {
#define HLODR_GL_MEMBER(suffix, name) PFNGL##suffix##PROC name = nullptr;
  HLODR_GL_FUNCTIONS(HLODR_GL_MEMBER)
#undef HLODR_GL_MEMBER

  // Loads every entry point; returns the name of the first one missing, or "" when all loaded.
  template <class GetProc>
  std::string load(GetProc&& getProc) {
#define HLODR_GL_LOAD(suffix, name)                                  \
  name = reinterpret_cast<PFNGL##suffix##PROC>(getProc("gl" #name)); \
  if (!name) return "gl" #name;
    HLODR_GL_FUNCTIONS(HLODR_GL_LOAD)
#undef HLODR_GL_LOAD
    return "";
  }
};

}  // namespace renderer
