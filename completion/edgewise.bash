# bash completion for edgewise(1): commands, each command's options, the
# values of the options that take a word from a fixed list, and files where
# a file or directory is expected.  Installed as
# share/bash-completion/completions/edgewise; or `source` it.
# Written by edgewise_gen (make cli_docs) from the option table, cli/options.c:
# edit that, not this.

_edgewise()
{
    local cur=${COMP_WORDS[COMP_CWORD]} prev= cmd=${COMP_WORDS[1]-} w
    [ "$COMP_CWORD" -gt 0 ] && prev=${COMP_WORDS[COMP_CWORD-1]}
    COMPREPLY=()

    local commands='render demo views info bench hsr soak shots fly view timedemo help'
    if [ "$COMP_CWORD" -le 1 ]; then
        COMPREPLY=($(compgen -W "$commands --help --version" -- "$cur"))
        return 0
    fi
    # render and view of builtin:polyhedra have their own options
    for w in "${COMP_WORDS[@]:2}"; do
        [ "$w" = builtin:polyhedra ] && case $cmd in render|view) cmd=$cmd-polyhedra ;; esac
    done

    # The values of options.
    case $cmd:$prev in
        render:--game|views:--game|info:--game|bench:--game|hsr:--game|soak:--game|shots:--game|fly:--game|view:--game|timedemo:--game)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -d -- "$cur")); return 0 ;;
        render:--data|views:--data|info:--data)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -d -- "$cur")); return 0 ;;
        render:--out|demo:--out)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        bench:--data|hsr:--data|soak:--data|view:--data)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -d -- "$cur")); return 0 ;;
        bench:--out)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        bench:--simd)
            COMPREPLY=($(compgen -W 'best sse2 avx2 avx512' -- "$cur")); return 0 ;;
        hsr:--methods)
            COMPREPLY=($(compgen -W 'edge edge-z spans zbuffer painter drawbuffer beamtree raycast reference' -- "$cur")); return 0 ;;
        hsr:--json)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        hsr:--heatmap)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -d -- "$cur")); return 0 ;;
        hsr:--svg)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        shots:--data|fly:--data)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -d -- "$cur")); return 0 ;;
        shots:--out)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -d -- "$cur")); return 0 ;;
        shots:--views)
            COMPREPLY=($(compgen -W 'best all' -- "$cur")); return 0 ;;
        shots:--manifest)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        shots:--contact-sheet)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        fly:--path)
            compopt -o filenames 2>/dev/null
            COMPREPLY=($(compgen -W 'views straight' -- "$cur") $(compgen -f -- "$cur")); return 0 ;;
        fly:--out)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        fly:--demo)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        fly:--cameras)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        view:--present)
            COMPREPLY=($(compgen -W 'auto surface texture software' -- "$cur")); return 0 ;;
        view:--script)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        view:--demo)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        view:--record)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        timedemo:--data)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -d -- "$cur")); return 0 ;;
        timedemo:--out)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        render-polyhedra:--out)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        view-polyhedra:--out)
            compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        render:--alias-raster|demo:--alias-raster|bench:--alias-raster|hsr:--alias-raster|soak:--alias-raster|shots:--alias-raster|fly:--alias-raster|view:--alias-raster|timedemo:--alias-raster)
            COMPREPLY=($(compgen -W 'auto affine subdiv masks sprite-cache' -- "$cur")); return 0 ;;
        render:--occlusion|demo:--occlusion|bench:--occlusion|hsr:--occlusion|soak:--occlusion|shots:--occlusion|fly:--occlusion|view:--occlusion|timedemo:--occlusion)
            COMPREPLY=($(compgen -W 'off auto always' -- "$cur")); return 0 ;;
        render:--hsr|demo:--hsr|bench:--hsr|hsr:--hsr|soak:--hsr|shots:--hsr|fly:--hsr|view:--hsr|timedemo:--hsr)
            COMPREPLY=($(compgen -W 'edge reference edge-z spans zbuffer painter drawbuffer beamtree raycast' -- "$cur")); return 0 ;;
        render:--color|demo:--color|bench:--color|hsr:--color|soak:--color|shots:--color|fly:--color|view:--color|timedemo:--color)
            COMPREPLY=($(compgen -W '8bit true' -- "$cur")); return 0 ;;
        render:--lighting|demo:--lighting|bench:--lighting|hsr:--lighting|soak:--lighting|shots:--lighting|fly:--lighting|view:--lighting|timedemo:--lighting)
            COMPREPLY=($(compgen -W 'cache two-pass' -- "$cur")); return 0 ;;
        render:--debug|demo:--debug|bench:--debug|hsr:--debug|soak:--debug|shots:--debug|fly:--debug|view:--debug|timedemo:--debug)
            COMPREPLY=($(compgen -W 'spans edges overdraw lighting textures mips builds' -- "$cur")); return 0 ;;
        render:--size|demo:--size|render:--view|demo:--view|\
        render:--pos|render:--angles|render:--fov|demo:--fov|\
        render:--time|demo:--time|render:--dlight|demo:--dlight|\
        render:--particles|demo:--particles|render:--threads|demo:--threads|\
        bench:--size|bench:--threads|bench:--passes|bench:--gap|\
        bench:--bands|hsr:--size|hsr:--threads|soak:--threads|\
        hsr:--repeat|hsr:--stress|soak:--frames|soak:--size|\
        soak:--seed|shots:--size|shots:--jobs|fly:--seconds|\
        fly:--fps|fly:--size|fly:--from|fly:--to|\
        fly:--threads|view:--size|view:--scale|view:--threads|\
        view:--fov|view:--view|timedemo:--size|timedemo:--threads|\
        timedemo:--at|timedemo:--to|render-polyhedra:--time|render-polyhedra:--size|\
        view-polyhedra:--size|render-polyhedra:--objects|view-polyhedra:--objects|view-polyhedra:--scale|\
        view-polyhedra:--time|view-polyhedra:--frames|render:--subdiv-threshold|demo:--subdiv-threshold|\
        bench:--subdiv-threshold|hsr:--subdiv-threshold|soak:--subdiv-threshold|shots:--subdiv-threshold|\
        fly:--subdiv-threshold|view:--subdiv-threshold|timedemo:--subdiv-threshold|render:--wateralpha|\
        demo:--wateralpha|bench:--wateralpha|hsr:--wateralpha|soak:--wateralpha|\
        shots:--wateralpha|fly:--wateralpha|view:--wateralpha|timedemo:--wateralpha|\
        render:--fog|demo:--fog|bench:--fog|hsr:--fog|\
        soak:--fog|shots:--fog|fly:--fog|view:--fog|\
        timedemo:--fog|render:--lightstyle|demo:--lightstyle|bench:--lightstyle|\
        hsr:--lightstyle|soak:--lightstyle|shots:--lightstyle|fly:--lightstyle|\
        view:--lightstyle|timedemo:--lightstyle|render:--gamma|demo:--gamma|\
        bench:--gamma|hsr:--gamma|soak:--gamma|shots:--gamma|\
        fly:--gamma|view:--gamma|timedemo:--gamma)
            return 0 ;;
    esac

    local opts
    case $cmd in
        render) opts='--help --game --data --size --view --pos --angles --fov --time --out --stats
                  --dlight --particles --threads --quiet --no-entities --alias-raster --subdiv-threshold
                  --full-zfill --occlusion --classic --wateralpha --fog --no-fog --no-waterwarp
                  --hsr --color --no-lit --dither --lighting --lightstyle --gamma --debug' ;;
        demo) opts='--help --size --view --fov --time --out --stats --dlight --particles --threads
                  --quiet --no-entities --alias-raster --subdiv-threshold --full-zfill --occlusion
                  --classic --wateralpha --fog --no-fog --no-waterwarp --hsr --color --no-lit
                  --dither --lighting --lightstyle --gamma --debug' ;;
        views) opts='--help --game --data --quiet' ;;
        info) opts='--help --game --data --quiet' ;;
        bench) opts='--help --game --data --size --threads --passes --gap --bands --table --out
                  --floor --per-view --cold --simd --quiet --no-entities --alias-raster --subdiv-threshold
                  --full-zfill --occlusion --classic --wateralpha --fog --no-fog --no-waterwarp
                  --hsr --color --no-lit --dither --lighting --lightstyle --gamma --debug' ;;
        hsr) opts='--help --game --data --quiet --methods --size --threads --repeat --json
                  --heatmap --svg --stress --no-entities --alias-raster --subdiv-threshold
                  --full-zfill --occlusion --classic --wateralpha --fog --no-fog --no-waterwarp
                  --hsr --color --no-lit --dither --lighting --lightstyle --gamma --debug' ;;
        soak) opts='--help --game --quiet --data --threads --frames --size --seed --no-entities
                  --alias-raster --subdiv-threshold --full-zfill --occlusion --classic --wateralpha
                  --fog --no-fog --no-waterwarp --hsr --color --no-lit --dither --lighting
                  --lightstyle --gamma --debug' ;;
        shots) opts='--help --game --quiet --data --out --size --views --jobs --force --manifest
                  --contact-sheet --no-entities --alias-raster --subdiv-threshold --full-zfill
                  --occlusion --classic --wateralpha --fog --no-fog --no-waterwarp --hsr
                  --color --no-lit --dither --lighting --lightstyle --gamma --debug' ;;
        fly) opts='--help --game --quiet --data --path --seconds --fps --size --out --demo
                  --from --to --threads --cameras --no-entities --alias-raster --subdiv-threshold
                  --full-zfill --occlusion --classic --wateralpha --fog --no-fog --no-waterwarp
                  --hsr --color --no-lit --dither --lighting --lightstyle --gamma --debug' ;;
        view) opts='--help --game --quiet --data --size --scale --threads --fov --view --fullscreen
                  --present --script --demo --record --no-entities --alias-raster --subdiv-threshold
                  --full-zfill --occlusion --classic --wateralpha --fog --no-fog --no-waterwarp
                  --hsr --color --no-lit --dither --lighting --lightstyle --gamma --debug' ;;
        timedemo) opts='--help --game --data --size --threads --out --at --to --quiet --no-entities
                  --alias-raster --subdiv-threshold --full-zfill --occlusion --classic --wateralpha
                  --fog --no-fog --no-waterwarp --hsr --color --no-lit --dither --lighting
                  --lightstyle --gamma --debug' ;;
        render-polyhedra) opts='--help --time --size --objects --out --stats --independent --zbuffer' ;;
        view-polyhedra) opts='--help --size --objects --scale --time --frames --out' ;;
        *) return 0 ;;
    esac
    if [[ $cur == -* ]]; then
        COMPREPLY=($(compgen -W "$opts" -- "$cur"))
    elif [ "$cmd" != demo ]; then
        # MAP: the built-in scene, .bsp files, directories to walk into.
        compopt -o filenames 2>/dev/null
        COMPREPLY=($(compgen -W 'builtin builtin:polyhedra' -- "$cur")
                   $(compgen -d -- "$cur")
                   $(compgen -f -X '!*.bsp' -- "$cur"))
    fi
    return 0
}
complete -F _edgewise edgewise
