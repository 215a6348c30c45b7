# Copies the outside engines' adapters (engines/outside: *.mjs, package.json, suite/) into the build
# folder's outside/, with node_modules a symbolic link to the source tree's installed packages: the
# binary reads its default suite from outside/suite beside it, so a build copied elsewhere runs the
# adapters it carries. The copy is redone whole, so a file removed from the sources goes too.
#   cmake -DSRC=<source>/engines/outside -DDST=<build>/outside -DSTAMP=<file> -P copy_outside.cmake
foreach(sub suite)
  file(REMOVE_RECURSE ${DST}/${sub})
endforeach()
file(GLOB old ${DST}/*.mjs ${DST}/package.json)
if(old)
  file(REMOVE ${old})
endif()
file(MAKE_DIRECTORY ${DST}/suite)
file(GLOB adapters ${SRC}/*.mjs ${SRC}/package.json)
file(GLOB suite ${SRC}/suite/*.json ${SRC}/suite/*.md)
file(COPY ${adapters} DESTINATION ${DST})
file(COPY ${suite} DESTINATION ${DST}/suite)
if(NOT IS_SYMLINK ${DST}/node_modules)
  file(REMOVE_RECURSE ${DST}/node_modules)
  file(CREATE_LINK ${SRC}/node_modules ${DST}/node_modules SYMBOLIC)
endif()
file(TOUCH ${STAMP})
