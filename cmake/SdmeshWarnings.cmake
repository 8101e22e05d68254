# Warnings for sdmesh's own targets only (never for dependencies' headers).
function(sdmesh_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                                           -Wno-sign-conversion)
endfunction()
