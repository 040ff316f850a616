#!/bin/sh
# The library as a package (CMakeLists.txt registers this as `install_test`):
# installs the build into a temporary prefix, builds examples/ and
# tests/install_check.c with nothing but `pkg-config --cflags --libs edgewise`
# (against libedgewise.so and, with --static, against libedgewise.a), runs
# them on the built-in map and compares their pictures with `edgewise render
# builtin`; checks the exported symbols, the man page and the bash completion.
#
# Environment (set by ctest): EW_BUILD_DIR, EW_SOURCE, EW_CC, EW_EXTRA_CFLAGS
# (the sanitizer flags in the ASan build), EW_HAVE_SHARED (0 in the ASan
# build: no shared library there, so only the static half runs).
set -eu

: "${EW_BUILD_DIR:?}" "${EW_SOURCE:?}"
CC=${EW_CC:-cc}
EXTRA=${EW_EXTRA_CFLAGS:-}
HAVE_SHARED=${EW_HAVE_SHARED:-1}

TMP=$(mktemp -d "${TMPDIR:-/tmp}/ew-install.XXXXXX")
trap 'rm -rf "$TMP"' EXIT INT TERM
P=$TMP/prefix
fail() { echo "install_test: FAIL: $*" >&2; exit 1; }
note() { echo "install_test: $*"; }
SKIPPED=  # set when a part could not run: exit 77, which ctest reports as skipped

# ---- install --------------------------------------------------------------
cmake --install "$EW_BUILD_DIR" --prefix "$P" >"$TMP/install.log" 2>&1 ||
    { cat "$TMP/install.log" >&2; fail "cmake --install"; }
note "installed files:"
(cd "$P" && find . -type f -o -type l | sort | sed 's/^/  /')

for f in include/edgewise.h include/edgewise_lab.h lib/libedgewise.a \
         lib/pkgconfig/edgewise.pc bin/edgewise share/man/man1/edgewise.1 \
         share/bash-completion/completions/edgewise; do
    [ -s "$P/$f" ] || fail "$f not installed"
done
[ -x "$P/bin/edgewise" ] || fail "bin/edgewise is not executable"
VERSION=$("$P/bin/edgewise" --version | sed -n 's/^edgewise //p')
[ -n "$VERSION" ] || fail "edgewise --version printed no version"
MAJOR=${VERSION%%.*}
# The installed command runs on the installed shared library (its run path
# $ORIGIN/../lib), where the build made one.
if [ "${EW_HAVE_SHARED:-0}" = 1 ] && command -v readelf >/dev/null 2>&1; then
    readelf -d "$P/bin/edgewise" | grep -q "NEEDED.*\[libedgewise\.so\.$MAJOR\]" ||
        fail "bin/edgewise does not link libedgewise.so.$MAJOR"
    readelf -d "$P/bin/edgewise" | grep -q 'R.*PATH.*\$ORIGIN' ||
        fail "bin/edgewise has no \$ORIGIN run path"
    note "bin/edgewise runs on lib/libedgewise.so.$MAJOR"
fi

export PKG_CONFIG_PATH="$P/lib/pkgconfig"
PC_VERSION=$(pkg-config --modversion edgewise) || fail "pkg-config does not find edgewise.pc"
[ "$PC_VERSION" = "$VERSION" ] || fail "edgewise.pc says $PC_VERSION, edgewise --version $VERSION"
PC_CFLAGS=$(pkg-config --cflags edgewise)
PC_LIBS=$(pkg-config --libs edgewise)
PC_STATIC=$(pkg-config --static --libs edgewise)
note "pkg-config --cflags --libs edgewise: $PC_CFLAGS $PC_LIBS"
note "pkg-config --static --libs edgewise: $PC_STATIC"
# The .pc finds its prefix from where it is installed.
[ "$(cd "$(pkg-config --variable=includedir edgewise)" && pwd -P)" = "$(cd "$P/include" && pwd -P)" ] ||
    fail "edgewise.pc's includedir is not $P/include"
case " $PC_STATIC " in *" -lpng"*" -lm "*) ;; *) fail "--static lacks -lpng/-lm: $PC_STATIC" ;; esac
case " $PC_STATIC " in *" -pthread "*) ;; *) fail "--static lacks -pthread: $PC_STATIC" ;; esac

# ---- the shared library: soname and exactly the EW_API symbols -------------
if [ "$HAVE_SHARED" = 1 ]; then
    [ -f "$P/lib/libedgewise.so.$VERSION" ] || fail "lib/libedgewise.so.$VERSION missing"
    [ "$(readlink "$P/lib/libedgewise.so.$MAJOR")" = "libedgewise.so.$VERSION" ] ||
        fail "libedgewise.so.$MAJOR is not a link to libedgewise.so.$VERSION"
    [ "$(readlink "$P/lib/libedgewise.so")" = "libedgewise.so.$MAJOR" ] ||
        fail "libedgewise.so is not a link to libedgewise.so.$MAJOR"
    SONAME=$(objdump -p "$P/lib/libedgewise.so.$VERSION" | awk '$1 == "SONAME" { print $2 }')
    [ "$SONAME" = "libedgewise.so.$MAJOR" ] || fail "soname is '$SONAME'"
    nm -D --defined-only "$P/lib/libedgewise.so" | awk '{ print $NF }' |
        grep -v -e '^_edata$' -e '^_end$' -e '^__bss_start$' -e '^_init$' -e '^_fini$' |
        sort >"$TMP/exported"
    grep -h '^EW_API ' "$P/include/edgewise.h" "$P/include/edgewise_lab.h" |
        sed 's/(.*//; s/.*[ *]//' | sort >"$TMP/declared"
    diff "$TMP/declared" "$TMP/exported" >"$TMP/symdiff" ||
        { cat "$TMP/symdiff" >&2; fail "exported symbols (>) differ from the EW_API declarations (<)"; }
    note "libedgewise.so: soname $SONAME, $(wc -l <"$TMP/exported") symbols, exactly the EW_API functions"
else
    [ ! -e "$P/lib/libedgewise.so" ] || fail "a shared library where none was built"
    note "no shared library in this build (sanitizer build): static half only"
fi

# ---- build the examples with pkg-config only -------------------------------
build() { # build NAME SOURCE KIND
    out=$TMP/$1-$3
    if [ "$3" = shared ]; then
        libs="$PC_LIBS"
    else # -l:libedgewise.a: the archive even though the .so sits beside it
        libs=$(echo "$PC_STATIC" | sed 's/-ledgewise\b/-l:libedgewise.a/')
    fi
    # shellcheck disable=SC2086
    "$CC" -std=c11 -Wall -Wextra -Werror $EXTRA -o "$out" "$2" $PC_CFLAGS $libs ||
        fail "building $1 ($3)"
    if objdump -p "$out" | grep -q 'NEEDED.*libedgewise'; then linked=shared; else linked=static; fi
    [ "$linked" = "$3" ] || fail "$1 ($3) is linked $linked"
}
KINDS=static
[ "$HAVE_SHARED" = 1 ] && KINDS="shared static"
export LD_LIBRARY_PATH="$P/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"

SIZE=320x240
"$P/bin/edgewise" render builtin --no-entities --size $SIZE --out "$TMP/cli.png" --quiet >/dev/null 2>"$TMP/cli.err" ||
    fail "edgewise render builtin"
for kind in $KINDS; do
    build render_png "$EW_SOURCE/examples/render_png.c" $kind
    build render_buffer "$EW_SOURCE/examples/render_buffer.c" $kind
    build install_check "$EW_SOURCE/tests/install_check.c" $kind
    check=$TMP/install_check-$kind
    [ "$kind" = shared ] && CLI_SUM=$("$check" sum "$TMP/cli.png")
    [ "$kind" = static ] && [ -z "${CLI_SUM:-}" ] && CLI_SUM=$("$check" sum "$TMP/cli.png")

    "$TMP/render_png-$kind" builtin "$TMP/ex-$kind.png" $SIZE >/dev/null || fail "render_png ($kind)"
    [ "$(od -An -tx1 -N8 "$TMP/ex-$kind.png" | tr -d ' \n')" = 89504e470d0a1a0a ] ||
        fail "render_png ($kind) did not write a PNG"
    [ "$("$check" size "$TMP/ex-$kind.png")" = "320 240" ] || fail "render_png ($kind): not 320x240"

    BUF_SUM=$("$TMP/render_buffer-$kind" builtin $SIZE "$TMP/ex-$kind.ppm") || fail "render_buffer ($kind)"
    [ "$BUF_SUM" = "$CLI_SUM" ] ||
        fail "render_buffer ($kind) '$BUF_SUM' != edgewise render builtin '$CLI_SUM'"
    [ "$("$check" sum "$TMP/ex-$kind.ppm")" = "$CLI_SUM" ] || fail "render_buffer ($kind): PPM differs"
    [ "$("$check" sum "$TMP/ex-$kind.png")" = "$CLI_SUM" ] || fail "render_png ($kind): PNG differs"
    note "$kind: render_png wrote a 320x240 PNG; render_buffer, its PPM, render_png's PNG" \
         "and 'edgewise render builtin --no-entities' all: $CLI_SUM"
done

# ---- the man page: renders, and names every command and option -------------
MAN=$P/share/man/man1/edgewise.1
COMMANDS=$("$P/bin/edgewise" help | sed -n '/^commands:/,/^$/p' | awk 'NR > 1 && $1 !~ /^-/ { sub(",", "", $1); print $1 }')
[ -n "$COMMANDS" ] || fail "no commands in edgewise help"
OPTIONS=$({ "$P/bin/edgewise" help; for c in $COMMANDS; do "$P/bin/edgewise" "$c" --help; done; } |
          grep -o -- '--[a-z][a-z-]*' | sort -u)
for c in $COMMANDS; do
    grep -q "^\.SS $c\b" "$MAN" || fail "man page: no section for '$c'"
done
for o in $OPTIONS; do
    grep -qF -- "$(echo "$o" | sed 's/-/\\-/g')" "$MAN" || fail "man page: option $o missing"
done
if command -v groff >/dev/null 2>&1; then
    groff -man -Tutf8 -ww -z "$MAN" 2>"$TMP/groff.err"
    [ ! -s "$TMP/groff.err" ] || { cat "$TMP/groff.err" >&2; fail "groff warns about the man page"; }
fi
if command -v man >/dev/null 2>&1; then
    MANWIDTH=80 man -l "$MAN" 2>"$TMP/man.err" | col -b 2>/dev/null >"$TMP/man.txt" || true
    grep -q '^NAME' "$TMP/man.txt" && grep -q 'edgewise render' "$TMP/man.txt" ||
        { cat "$TMP/man.err" >&2; fail "man -l does not render the man page"; }
    note "man -l: $(wc -l <"$TMP/man.txt") lines; every command ($(echo $COMMANDS)) and $(echo "$OPTIONS" | wc -l) options covered"
elif command -v groff >/dev/null 2>&1; then
    note "groff: renders without warnings; every command and option covered"
else
    note "SKIP: neither man nor groff installed (Debian package groff-base): the page's text was checked, not its rendering"
    SKIPPED=1
fi

# ---- bash completion -------------------------------------------------------
COMP=$P/share/bash-completion/completions/edgewise
complete_line() { # complete_line WORD... : what the completion offers for the last word
    bash -c '. "$1"; shift; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _edgewise; printf "%s\n" "${COMPREPLY[@]}"' \
        sh "$COMP" "$@"
}
bash -c ". '$COMP' && complete -p edgewise" | grep -q '_edgewise' || fail "completion not registered"
for c in $COMMANDS; do
    complete_line edgewise "" | grep -qx "$c" || fail "completion: command $c not offered"
done
# Each command's options as its --help lists them (render, demo, views and
# info print the common usage text: render takes all of it).
opts_of() {
    case $1 in
        render) "$P/bin/edgewise" help | sed -n '/^render options:/,/^demo options/p' ;;
        bench|hsr|soak|shots|view) "$P/bin/edgewise" "$1" --help ;;
        views|info) echo "--data --quiet" ;;
        demo) "$P/bin/edgewise" help | sed -n '/^demo options/,/^$/p; /^what is drawn/,/^$/p' ;;
    esac | grep -o -- '--[a-z][a-z-]*' | grep -vx -- --version | sort -u
}
for c in $COMMANDS; do
    [ "$c" = help ] && continue
    for o in $(opts_of "$c"); do
        complete_line edgewise "$c" -- | grep -qx -- "$o" || fail "completion: $c $o not offered"
    done
done
[ "$(complete_line edgewise render --color "")" = "$(printf '8bit\ntrue')" ] ||
    fail "completion: render --color does not offer 8bit, true"
note "bash completion: every command and every option of each command's --help"
note "OK"
[ -z "$SKIPPED" ] || exit 77
