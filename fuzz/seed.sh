#!/bin/sh
# Copies the seed files into fuzz/corpus/<target>/ (git-ignored): the project's meshes/*.msh
# and, when it sits beside the project, the shared corpus ../shared/corpus/{cdb,msh,inp}.
set -e
here=$(cd "$(dirname "$0")" && pwd)
shared="$here/../../shared/corpus"
for t in cdb msh inp; do
    mkdir -p "$here/corpus/$t"
    if [ -d "$shared/$t" ]; then
        cp "$shared/$t"/* "$here/corpus/$t/"
    fi
done
cp "$here"/../meshes/*.msh "$here/corpus/msh/"
chmod -R u+w "$here/corpus"
ls "$here/corpus"/* | wc -l
