# A checkpoint altered after it was written (here: not one at all).
mkdir -p checkpoints
printf 'SCREE-CHECKPOINT and then nothing that a checkpoint holds' > checkpoints/0.005.ckpt
