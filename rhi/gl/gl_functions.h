// The OpenGL 4.5 core entry points the GL backend uses, loaded at run time through the context
// provider's get-proc-address (eglGetProcAddress / OSMesaGetProcAddress). No loader library:
// the list below is the whole surface, so adding a call means adding a line here.
//
// Calls are written gl.Name(...) on a GlFunctions table owned by the device.
#pragma once

#include <GL/glcorearb.h>

#include <string>

namespace parity::rhi::gl {

// X(PFN type from glcorearb.h, name without the "gl" prefix)
#define PARITY_GL_FUNCTIONS(X)                                                          \
  /* state and queries */                                                               \
  X(PFNGLGETERRORPROC, GetError)                                                        \
  X(PFNGLGETSTRINGPROC, GetString)                                                      \
  X(PFNGLGETSTRINGIPROC, GetStringi)                                                    \
  X(PFNGLGETINTEGERVPROC, GetIntegerv)                                                  \
  X(PFNGLGETFLOATVPROC, GetFloatv)                                                      \
  X(PFNGLGETINTEGERI_VPROC, GetIntegeri_v)                                              \
  X(PFNGLGETINTEGER64VPROC, GetInteger64v)                                              \
  X(PFNGLGETQUERYIVPROC, GetQueryiv)                                                    \
  X(PFNGLENABLEPROC, Enable)                                                            \
  X(PFNGLDISABLEPROC, Disable)                                                          \
  X(PFNGLENABLEIPROC, Enablei)                                                          \
  X(PFNGLDISABLEIPROC, Disablei)                                                        \
  X(PFNGLFINISHPROC, Finish)                                                            \
  X(PFNGLFLUSHPROC, Flush)                                                              \
  X(PFNGLCLIPCONTROLPROC, ClipControl)                                                  \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                                                  \
  X(PFNGLPROVOKINGVERTEXPROC, ProvokingVertex)                                          \
  X(PFNGLPOINTPARAMETERIPROC, PointParameteri)                                          \
  X(PFNGLFRONTFACEPROC, FrontFace)                                                      \
  X(PFNGLCULLFACEPROC, CullFace)                                                        \
  X(PFNGLPOLYGONMODEPROC, PolygonMode)                                                  \
  X(PFNGLPOLYGONOFFSETPROC, PolygonOffset)                                              \
  X(PFNGLDEPTHFUNCPROC, DepthFunc)                                                      \
  X(PFNGLDEPTHMASKPROC, DepthMask)                                                      \
  X(PFNGLDEPTHRANGEINDEXEDPROC, DepthRangeIndexed)                                      \
  X(PFNGLSTENCILFUNCSEPARATEPROC, StencilFuncSeparate)                                  \
  X(PFNGLSTENCILOPSEPARATEPROC, StencilOpSeparate)                                      \
  X(PFNGLSTENCILMASKSEPARATEPROC, StencilMaskSeparate)                                  \
  X(PFNGLCOLORMASKIPROC, ColorMaski)                                                    \
  X(PFNGLBLENDFUNCSEPARATEIPROC, BlendFuncSeparatei)                                    \
  X(PFNGLBLENDEQUATIONSEPARATEIPROC, BlendEquationSeparatei)                            \
  X(PFNGLBLENDCOLORPROC, BlendColor)                                                    \
  X(PFNGLVIEWPORTINDEXEDFPROC, ViewportIndexedf)                                        \
  X(PFNGLSCISSORINDEXEDPROC, ScissorIndexed)                                            \
  X(PFNGLVIEWPORTARRAYVPROC, ViewportArrayv)                                            \
  X(PFNGLSCISSORARRAYVPROC, ScissorArrayv)                                              \
  X(PFNGLDEPTHRANGEARRAYVPROC, DepthRangeArrayv)                                        \
  /* debug output */                                                                    \
  X(PFNGLDEBUGMESSAGECALLBACKPROC, DebugMessageCallback)                                \
  X(PFNGLDEBUGMESSAGECONTROLPROC, DebugMessageControl)                                  \
  X(PFNGLOBJECTLABELPROC, ObjectLabel)                                                  \
  X(PFNGLPUSHDEBUGGROUPPROC, PushDebugGroup)                                            \
  X(PFNGLPOPDEBUGGROUPPROC, PopDebugGroup)                                              \
  /* buffers */                                                                         \
  X(PFNGLCREATEBUFFERSPROC, CreateBuffers)                                              \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                              \
  X(PFNGLNAMEDBUFFERSTORAGEPROC, NamedBufferStorage)                                    \
  X(PFNGLMAPNAMEDBUFFERRANGEPROC, MapNamedBufferRange)                                  \
  X(PFNGLUNMAPNAMEDBUFFERPROC, UnmapNamedBuffer)                                        \
  X(PFNGLNAMEDBUFFERSUBDATAPROC, NamedBufferSubData)                                    \
  X(PFNGLGETNAMEDBUFFERSUBDATAPROC, GetNamedBufferSubData)                              \
  X(PFNGLCOPYNAMEDBUFFERSUBDATAPROC, CopyNamedBufferSubData)                            \
  X(PFNGLBINDBUFFERRANGEPROC, BindBufferRange)                                          \
  /* textures and samplers */                                                           \
  X(PFNGLCREATETEXTURESPROC, CreateTextures)                                            \
  X(PFNGLTEXTUREBUFFERRANGEPROC, TextureBufferRange)                                    \
  X(PFNGLGENTEXTURESPROC, GenTextures)                                                  \
  X(PFNGLDELETETEXTURESPROC, DeleteTextures)                                            \
  X(PFNGLTEXTURESTORAGE1DPROC, TextureStorage1D)                                        \
  X(PFNGLTEXTURESTORAGE2DPROC, TextureStorage2D)                                        \
  X(PFNGLTEXTURESTORAGE3DPROC, TextureStorage3D)                                        \
  X(PFNGLTEXTURESTORAGE2DMULTISAMPLEPROC, TextureStorage2DMultisample)                  \
  X(PFNGLTEXTURESUBIMAGE1DPROC, TextureSubImage1D)                                      \
  X(PFNGLTEXTURESUBIMAGE2DPROC, TextureSubImage2D)                                      \
  X(PFNGLTEXTURESUBIMAGE3DPROC, TextureSubImage3D)                                      \
  X(PFNGLTEXTUREVIEWPROC, TextureView)                                                  \
  X(PFNGLTEXTUREPARAMETERIPROC, TextureParameteri)                                      \
  X(PFNGLGETTEXTURESUBIMAGEPROC, GetTextureSubImage)                                    \
  X(PFNGLCOPYIMAGESUBDATAPROC, CopyImageSubData)                                        \
  X(PFNGLBINDTEXTUREUNITPROC, BindTextureUnit)                                          \
  X(PFNGLBINDIMAGETEXTUREPROC, BindImageTexture)                                        \
  X(PFNGLCREATESAMPLERSPROC, CreateSamplers)                                            \
  X(PFNGLDELETESAMPLERSPROC, DeleteSamplers)                                            \
  X(PFNGLSAMPLERPARAMETERIPROC, SamplerParameteri)                                      \
  X(PFNGLSAMPLERPARAMETERFPROC, SamplerParameterf)                                      \
  X(PFNGLSAMPLERPARAMETERFVPROC, SamplerParameterfv)                                    \
  X(PFNGLSAMPLERPARAMETERIIVPROC, SamplerParameterIiv)                                  \
  X(PFNGLBINDSAMPLERPROC, BindSampler)                                                  \
  /* shaders and programs */                                                            \
  X(PFNGLCREATESHADERPROC, CreateShader)                                                \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                                                \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                                              \
  X(PFNGLSHADERBINARYPROC, ShaderBinary)                                                \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                                                  \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                                        \
  X(PFNGLDELETESHADERPROC, DeleteShader)                                                \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                              \
  X(PFNGLATTACHSHADERPROC, AttachShader)                                                \
  X(PFNGLDETACHSHADERPROC, DetachShader)                                                \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                                                  \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                                \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                                      \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                              \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                                                    \
  X(PFNGLPROGRAMPARAMETERIPROC, ProgramParameteri)                                      \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                                    \
  X(PFNGLPROGRAMUNIFORM1IPROC, ProgramUniform1i)                                        \
  X(PFNGLGETATTRIBLOCATIONPROC, GetAttribLocation)                                     \
  X(PFNGLBINDATTRIBLOCATIONPROC, BindAttribLocation)                                  \
  X(PFNGLBINDFRAGDATALOCATIONPROC, BindFragDataLocation)                              \
  X(PFNGLGETPROGRAMRESOURCEINDEXPROC, GetProgramResourceIndex)                        \
  X(PFNGLPROGRAMUNIFORM1FVPROC, ProgramUniform1fv)                                    \
  X(PFNGLPROGRAMUNIFORM2FVPROC, ProgramUniform2fv)                                    \
  X(PFNGLPROGRAMUNIFORM3FVPROC, ProgramUniform3fv)                                    \
  X(PFNGLPROGRAMUNIFORM4FVPROC, ProgramUniform4fv)                                    \
  X(PFNGLPROGRAMUNIFORM1IVPROC, ProgramUniform1iv)                                    \
  X(PFNGLPROGRAMUNIFORM2IVPROC, ProgramUniform2iv)                                    \
  X(PFNGLPROGRAMUNIFORM3IVPROC, ProgramUniform3iv)                                    \
  X(PFNGLPROGRAMUNIFORM4IVPROC, ProgramUniform4iv)                                    \
  X(PFNGLPROGRAMUNIFORM1UIVPROC, ProgramUniform1uiv)                                  \
  X(PFNGLPROGRAMUNIFORM2UIVPROC, ProgramUniform2uiv)                                  \
  X(PFNGLPROGRAMUNIFORM3UIVPROC, ProgramUniform3uiv)                                  \
  X(PFNGLPROGRAMUNIFORM4UIVPROC, ProgramUniform4uiv)                                  \
  X(PFNGLPROGRAMUNIFORM1DVPROC, ProgramUniform1dv)                                    \
  X(PFNGLPROGRAMUNIFORM2DVPROC, ProgramUniform2dv)                                    \
  X(PFNGLPROGRAMUNIFORM3DVPROC, ProgramUniform3dv)                                    \
  X(PFNGLPROGRAMUNIFORM4DVPROC, ProgramUniform4dv)                                    \
  X(PFNGLPROGRAMUNIFORMMATRIX2FVPROC, ProgramUniformMatrix2fv)                        \
  X(PFNGLPROGRAMUNIFORMMATRIX3FVPROC, ProgramUniformMatrix3fv)                        \
  X(PFNGLPROGRAMUNIFORMMATRIX4FVPROC, ProgramUniformMatrix4fv)                        \
  X(PFNGLPROGRAMUNIFORMMATRIX2X3FVPROC, ProgramUniformMatrix2x3fv)                    \
  X(PFNGLPROGRAMUNIFORMMATRIX3X2FVPROC, ProgramUniformMatrix3x2fv)                    \
  X(PFNGLPROGRAMUNIFORMMATRIX2X4FVPROC, ProgramUniformMatrix2x4fv)                    \
  X(PFNGLPROGRAMUNIFORMMATRIX4X2FVPROC, ProgramUniformMatrix4x2fv)                    \
  X(PFNGLPROGRAMUNIFORMMATRIX3X4FVPROC, ProgramUniformMatrix3x4fv)                    \
  X(PFNGLPROGRAMUNIFORMMATRIX4X3FVPROC, ProgramUniformMatrix4x3fv)                    \
  X(PFNGLPROGRAMUNIFORMMATRIX2DVPROC, ProgramUniformMatrix2dv)                        \
  X(PFNGLPROGRAMUNIFORMMATRIX3DVPROC, ProgramUniformMatrix3dv)                        \
  X(PFNGLPROGRAMUNIFORMMATRIX4DVPROC, ProgramUniformMatrix4dv)                        \
  X(PFNGLPROGRAMUNIFORMMATRIX2X3DVPROC, ProgramUniformMatrix2x3dv)                    \
  X(PFNGLPROGRAMUNIFORMMATRIX3X2DVPROC, ProgramUniformMatrix3x2dv)                    \
  X(PFNGLPROGRAMUNIFORMMATRIX2X4DVPROC, ProgramUniformMatrix2x4dv)                    \
  X(PFNGLPROGRAMUNIFORMMATRIX4X2DVPROC, ProgramUniformMatrix4x2dv)                    \
  X(PFNGLPROGRAMUNIFORMMATRIX3X4DVPROC, ProgramUniformMatrix3x4dv)                    \
  X(PFNGLPROGRAMUNIFORMMATRIX4X3DVPROC, ProgramUniformMatrix4x3dv)                    \
  X(PFNGLGETPROGRAMINTERFACEIVPROC, GetProgramInterfaceiv)                              \
  X(PFNGLGETPROGRAMRESOURCENAMEPROC, GetProgramResourceName)                            \
  X(PFNGLGETPROGRAMRESOURCEIVPROC, GetProgramResourceiv)                                \
  X(PFNGLUNIFORMBLOCKBINDINGPROC, UniformBlockBinding)                                  \
  X(PFNGLSHADERSTORAGEBLOCKBINDINGPROC, ShaderStorageBlockBinding)                      \
  /* vertex arrays */                                                                   \
  X(PFNGLCREATEVERTEXARRAYSPROC, CreateVertexArrays)                                    \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                                    \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                                          \
  X(PFNGLENABLEVERTEXARRAYATTRIBPROC, EnableVertexArrayAttrib)                          \
  X(PFNGLVERTEXARRAYATTRIBFORMATPROC, VertexArrayAttribFormat)                          \
  X(PFNGLVERTEXARRAYATTRIBIFORMATPROC, VertexArrayAttribIFormat)                        \
  X(PFNGLVERTEXARRAYATTRIBLFORMATPROC, VertexArrayAttribLFormat)                        \
  X(PFNGLVERTEXARRAYATTRIBBINDINGPROC, VertexArrayAttribBinding)                        \
  X(PFNGLVERTEXARRAYBINDINGDIVISORPROC, VertexArrayBindingDivisor)                      \
  X(PFNGLVERTEXARRAYVERTEXBUFFERPROC, VertexArrayVertexBuffer)                          \
  X(PFNGLVERTEXARRAYELEMENTBUFFERPROC, VertexArrayElementBuffer)                        \
  /* framebuffers */                                                                    \
  X(PFNGLCREATEFRAMEBUFFERSPROC, CreateFramebuffers)                                    \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                                    \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                          \
  X(PFNGLNAMEDFRAMEBUFFERTEXTUREPROC, NamedFramebufferTexture)                          \
  X(PFNGLNAMEDFRAMEBUFFERTEXTURELAYERPROC, NamedFramebufferTextureLayer)                \
  X(PFNGLNAMEDFRAMEBUFFERDRAWBUFFERSPROC, NamedFramebufferDrawBuffers)                  \
  X(PFNGLNAMEDFRAMEBUFFERREADBUFFERPROC, NamedFramebufferReadBuffer)                    \
  X(PFNGLCHECKNAMEDFRAMEBUFFERSTATUSPROC, CheckNamedFramebufferStatus)                  \
  X(PFNGLCLEARNAMEDFRAMEBUFFERFVPROC, ClearNamedFramebufferfv)                          \
  X(PFNGLCLEARNAMEDFRAMEBUFFERIVPROC, ClearNamedFramebufferiv)                          \
  X(PFNGLCLEARNAMEDFRAMEBUFFERUIVPROC, ClearNamedFramebufferuiv)                        \
  X(PFNGLCLEARNAMEDFRAMEBUFFERFIPROC, ClearNamedFramebufferfi)                          \
  X(PFNGLBLITNAMEDFRAMEBUFFERPROC, BlitNamedFramebuffer)                                \
  /* draws, dispatches, synchronisation, timing */                                      \
  X(PFNGLDRAWARRAYSINSTANCEDBASEINSTANCEPROC, DrawArraysInstancedBaseInstance)          \
  X(PFNGLPATCHPARAMETERIPROC, PatchParameteri)                                          \
  X(PFNGLDRAWELEMENTSINSTANCEDBASEVERTEXBASEINSTANCEPROC,                               \
    DrawElementsInstancedBaseVertexBaseInstance)                                        \
  X(PFNGLDISPATCHCOMPUTEPROC, DispatchCompute)                                          \
  X(PFNGLMEMORYBARRIERPROC, MemoryBarrier)                                              \
  X(PFNGLCREATEQUERIESPROC, CreateQueries)                                              \
  X(PFNGLDELETEQUERIESPROC, DeleteQueries)                                              \
  X(PFNGLQUERYCOUNTERPROC, QueryCounter)                                                \
  X(PFNGLGETQUERYOBJECTUI64VPROC, GetQueryObjectui64v)

struct GlFunctions {
#define PARITY_GL_DECLARE(type, name) type name = nullptr;
  PARITY_GL_FUNCTIONS(PARITY_GL_DECLARE)
#undef PARITY_GL_DECLARE
};

using GlGetProcAddress = void* (*)(const char* name, void* userData);

// Fills every entry of *gl. Returns false with the missing names ("glFoo glBar") in *missing.
bool loadGlFunctions(GlFunctions* gl, GlGetProcAddress getProc, void* userData, std::string* missing);

}  // namespace parity::rhi::gl
