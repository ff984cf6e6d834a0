# omniview_add_proto_library(<target>
#     ROOT <dir>            import root of the .proto files (their `import "a/b.proto"` paths
#                           are relative to it)
#     PROTOS <file>...      .proto files, relative to ROOT
#     [COMMENT <text>])
#
# Generates C++ messages (protoc) and gRPC stubs (grpc_cpp_plugin) for PROTOS into
# ${CMAKE_CURRENT_BINARY_DIR}/gen at build time and builds them into a STATIC library
# <target> that exports that directory as a SYSTEM include path, so code includes
# "a/b.pb.h" / "a/b.grpc.pb.h" with the same paths as the imports.
# All files go through one protoc call, so a change to any of them regenerates the set
# (imports between them are then always consistent).
function(omniview_add_proto_library target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "ROOT;COMMENT" "PROTOS")
  if(NOT arg_ROOT OR NOT arg_PROTOS)
    message(FATAL_ERROR "omniview_add_proto_library(${target}): ROOT and PROTOS are required")
  endif()
  if(NOT arg_COMMENT)
    set(arg_COMMENT "Generating C++ code for ${target}")
  endif()

  set(gen_dir ${CMAKE_CURRENT_BINARY_DIR}/gen)
  file(MAKE_DIRECTORY ${gen_dir})
  set(proto_paths)
  set(gen_srcs)
  foreach(rel IN LISTS arg_PROTOS)
    string(REGEX REPLACE "\\.proto$" "" stem ${rel})
    list(APPEND proto_paths ${arg_ROOT}/${rel})
    list(APPEND gen_srcs
      ${gen_dir}/${stem}.pb.cc ${gen_dir}/${stem}.pb.h
      ${gen_dir}/${stem}.grpc.pb.cc ${gen_dir}/${stem}.grpc.pb.h)
  endforeach()

  add_custom_command(
    OUTPUT ${gen_srcs}
    COMMAND protobuf::protoc
      --proto_path=${arg_ROOT}
      --cpp_out=${gen_dir}
      --grpc_out=${gen_dir}
      --plugin=protoc-gen-grpc=$<TARGET_FILE:gRPC::grpc_cpp_plugin>
      ${proto_paths}
    DEPENDS ${proto_paths} protobuf::protoc gRPC::grpc_cpp_plugin
    COMMENT "${arg_COMMENT}"
    VERBATIM)

  add_library(${target} ${gen_srcs})
  target_include_directories(${target} SYSTEM PUBLIC ${gen_dir})
  target_link_libraries(${target} PUBLIC protobuf::libprotobuf gRPC::grpc++)
  # Generated code is not ours to warn about, and each file defines the same file-level
  # names (schemas, file_default_instances): one translation unit per file.
  target_compile_options(${target} PRIVATE -w)
  set_target_properties(${target} PROPERTIES UNITY_BUILD OFF)
endfunction()
