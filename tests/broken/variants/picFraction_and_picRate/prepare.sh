printf 'transfer FLIP;\npicFraction 1e-4;\npicRate 10;\n' > system/mpmSchemes
