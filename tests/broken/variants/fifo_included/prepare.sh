echo "#include \"extra\"" >> system/controlDict
mkfifo system/extra
