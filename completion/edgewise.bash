# bash completion for edgewise(1): commands, each command's options, the
# values of the options that take a word from a fixed list, and files where
# a file or directory is expected.  Installed as
# share/bash-completion/completions/edgewise; or `source` it.

_edgewise()
{
    local cur=${COMP_WORDS[COMP_CWORD]} prev= cmd=${COMP_WORDS[1]-}
    [ "$COMP_CWORD" -gt 0 ] && prev=${COMP_WORDS[COMP_CWORD-1]}
    COMPREPLY=()

    local commands='render demo views info bench hsr soak shots fly view help'
    if [ "$COMP_CWORD" -le 1 ]; then
        COMPREPLY=($(compgen -W "$commands --help --version" -- "$cur"))
        return 0
    fi

    # The values of options.
    case $prev in
        --alias-raster) COMPREPLY=($(compgen -W 'auto affine subdiv masks sprite-cache' -- "$cur")); return 0 ;;
        --occlusion)    COMPREPLY=($(compgen -W 'off auto always' -- "$cur")); return 0 ;;
        --hsr)          COMPREPLY=($(compgen -W 'edge reference' -- "$cur")); return 0 ;;
        --methods)      COMPREPLY=($(compgen -W 'edge reference' -- "$cur")); return 0 ;;
        --json|--svg)   compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        --heatmap)      compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -d -- "$cur")); return 0 ;;
        --color)        COMPREPLY=($(compgen -W '8bit true' -- "$cur")); return 0 ;;
        --lighting)     COMPREPLY=($(compgen -W 'cache two-pass' -- "$cur")); return 0 ;;
        --debug)        COMPREPLY=($(compgen -W 'spans edges overdraw lighting textures mips builds' -- "$cur"))
                        return 0 ;;
        --lightstyle)   return 0 ;;
        --views)        COMPREPLY=($(compgen -W 'best all' -- "$cur")); return 0 ;;
        --present)      COMPREPLY=($(compgen -W 'auto surface texture software' -- "$cur")); return 0 ;;
        --script|--record|--manifest|--contact-sheet|--cameras)
                        compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        --path)         compopt -o filenames 2>/dev/null
                        COMPREPLY=($(compgen -W 'views' -- "$cur") $(compgen -f -- "$cur")); return 0 ;;
        --data)         compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -d -- "$cur")); return 0 ;;
        --out)          compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- "$cur")); return 0 ;;
        --size|--view|--pos|--angles|--fov|--time|--dlight|--particles|--threads|\
        --subdiv-threshold|--wateralpha|--fog|--gamma|--passes|--bands|--frames|--seed|--scale|--jobs|--seconds|--fps|\
        --repeat|--stress)
                        return 0 ;;
    esac

    local drawn='--no-entities --alias-raster --subdiv-threshold --full-zfill --occlusion --classic
                 --wateralpha --fog --no-fog --no-waterwarp --hsr --color --no-lit --dither --lighting
                 --lightstyle --gamma --debug'
    local opts
    case $cmd in
        render) opts="--data --size --view --pos --angles --fov --time --out --stats --dlight
                      --particles --threads --quiet --help $drawn" ;;
        demo)   opts="--size --view --fov --time --out --stats --dlight --particles --threads
                      --quiet --help $drawn" ;;
        views|info) opts='--data --quiet --help' ;;
        bench)  opts="--data --size --threads --passes --gap --bands --table --out --floor --per-view --quiet --help $drawn" ;;
        hsr)    opts="--data --methods --size --threads --repeat --json --heatmap --svg --stress --quiet --help
                      $drawn" ;;
        soak)   opts="--data --frames --size --seed --threads --quiet --help $drawn" ;;
        shots)  opts="--data --out --size --views --jobs --force --manifest --contact-sheet --quiet --help $drawn" ;;
        fly)    opts="--data --path --seconds --fps --size --out --cameras --quiet --help $drawn" ;;
        view)   opts="--data --size --scale --threads --fov --view --fullscreen --present --script --record --quiet --help
                      $drawn" ;;
        *)      return 0 ;;
    esac
    if [[ $cur == -* ]]; then
        COMPREPLY=($(compgen -W "$opts" -- "$cur"))
    elif [ "$cmd" != demo ]; then
        # MAP: the built-in scene, .bsp files, directories to walk into.
        compopt -o filenames 2>/dev/null
        COMPREPLY=($(compgen -W 'builtin' -- "$cur")
                   $(compgen -d -- "$cur")
                   $(compgen -f -X '!*.bsp' -- "$cur"))
    fi
    return 0
}
complete -F _edgewise edgewise
